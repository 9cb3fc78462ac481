"""One-off reference for tests/meta/cma_es_authors_test.cpp (docs/cma_es.md, "The authors'
lambda = 1"): pycma's recombination of one generation with the C library's population and weights
for lambda = 1, K = 4 (lambda 4 + floor(3 ln 4) = 8, mu = 4, weights ln 5 - ln i), in the order
the authors' code ranked it for a positive meta-fitness (the evaluated sample 0 first, then the
unevaluated 7, 6, 5). Prints the samples and the new mean as C++ initialisers. Run outside the
build:

    python3 -m venv /tmp/pycma && /tmp/pycma/bin/pip install cma numpy
    /tmp/pycma/bin/python tools/pycma_authors_reference.py
"""
import math
import warnings

warnings.filterwarnings("ignore")
import cma  # noqa: E402

K = 4
LAMBDA = 4 + int(3 * math.log(K))
MU = LAMBDA // 2
WEIGHTS = [math.log(MU + 1) - math.log(i) for i in range(1, MU + 1)] + [0.0] * (LAMBDA - MU)


def main():
    es = cma.CMAEvolutionStrategy(K * [0.1], 0.5, {"popsize": LAMBDA, "CMA_recombination_weights": WEIGHTS,
                                                  "CMA_active": False, "seed": 3, "verbose": -9})
    x = es.ask()
    # pycma minimises: sample 0 best, then sample LAMBDA - 1, ..., sample 1 (distinct values, so
    # pycma's sort has no ties to break).
    f = [0.0] + [float(LAMBDA - i) for i in range(1, LAMBDA)]
    es.tell(x, f)
    print(f"// pycma {cma.__version__}: K = {K}, lambda = {LAMBDA}, mu = {MU}, x0 = 0.1, sigma0 = 0.5, seed 3")
    print("samples (one per row):")
    for row in x:
        print("  " + ", ".join(f"{float(v)!r}" for v in row) + ",")
    print("mean after tell:")
    print("  " + ", ".join(f"{float(v)!r}" for v in es.mean))


if __name__ == "__main__":
    main()
