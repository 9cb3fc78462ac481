"""A variation operator written in Python for MAP-Elites (Algorithm(..., variation=f)): f gets
two elites per offspring and a seed, its offspring are the ones evaluated, runs are
deterministic (by hand, stepped on threads, pickled mid-run), and mistakes are named."""
import pickle

import numpy as np
import pytest

import qdmeta

ME = {"algorithm": "map-elites", "seed": 5, "archive": {"bins": [20, 20]},
      "map_elites": {"batch_size": 50, "initial_population": 200}}


def sphere(x):
    f = -np.sum((x.astype(np.float64) - 0.5) ** 2, axis=1)
    return f.astype(np.float32), x[:, :2]


TASK = qdmeta.Task(sphere, genotype_size=6, base_feature_size=2, name="sphere6")


def iso_line(parents, partners, seed):
    """The iso+line operator in numpy, from its own generator."""
    rng = np.random.default_rng(seed)
    line = rng.normal(0.0, 0.2, size=(len(parents), 1))
    iso = rng.normal(0.0, 0.01, size=parents.shape)
    return np.clip(parents + iso + line * (partners - parents), 0.0, 1.0)


def test_offspring_are_the_functions_from_two_elites_each():
    seen = []

    def recording(parents, partners, seed):
        assert parents.dtype == partners.dtype == np.float32 and parents.shape == partners.shape == (50, 6)
        out = iso_line(parents, partners, seed)
        seen.append((parents, partners, seed, out))
        return out

    me = qdmeta.Algorithm(ME, task=TASK, variation=recording)
    me.tell(*sphere(me.ask()))  # the random initial population: no call
    assert not seen
    for _ in range(5):
        elites = {row.tobytes() for row in me.data()["solution"]}
        x = me.ask()
        parents, partners, seed, out = seen[-1]
        assert np.array_equal(x, out.astype(np.float32))
        assert all(row.tobytes() in elites for row in parents)
        assert all(row.tobytes() in elites for row in partners)
        me.tell(*sphere(x))
    assert len(seen) == 5 and len({s for _, _, s, _ in seen}) == 5  # a new seed each generation


def test_same_bits_by_hand_on_threads_and_after_pickling():
    by_hand = qdmeta.Algorithm(ME, task=TASK, variation=iso_line)
    stepped = qdmeta.Algorithm(ME, task=TASK, variation=iso_line)
    for _ in range(8):
        by_hand.tell(*sphere(by_hand.ask()))
        stepped.step(threads=2)
    copy = pickle.loads(pickle.dumps(stepped))
    for a in (by_hand, stepped, copy):
        for _ in range(4):
            a.step(threads=1)
    for a in (stepped, copy):
        assert np.array_equal(a.data()["solution"], by_hand.data()["solution"])
        assert np.array_equal(a.data()["objective"], by_hand.data()["objective"])
    plain = qdmeta.Algorithm(ME, task=TASK)
    for _ in range(12):
        plain.step()
    assert not np.array_equal(plain.data()["objective"], by_hand.data()["objective"])


def test_mistakes_are_named():
    me = qdmeta.Algorithm(ME, task=TASK, variation=lambda p, q, s: p + 2.0)
    me.step()
    with pytest.raises(qdmeta.InputError, match="row 0 gene 0 .* outside \\[0, 1\\]"):
        me.step()
    me = qdmeta.Algorithm(ME, task=TASK, variation=lambda p, q, s: p[:3])
    me.step()
    with pytest.raises(ValueError, match="variation's offspring"):
        me.step()

    def failing(p, q, s):
        raise RuntimeError("my operator broke")

    me = qdmeta.Algorithm(ME, task=TASK, variation=failing)
    me.step()
    with pytest.raises(RuntimeError, match="my operator broke"):
        me.step()
    with pytest.raises(TypeError, match="callable"):
        qdmeta.Algorithm(ME, task=TASK, variation=3)
    with pytest.raises(ValueError, match='"map-elites" only'):
        qdmeta.Algorithm({"algorithm": "aurora", "seed": 1}, task=TASK, variation=iso_line)
