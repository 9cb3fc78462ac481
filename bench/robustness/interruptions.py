#!/usr/bin/python3
"""The interruption matrix (issue 42): what an interrupted run or experiment leaves, and what the
next command makes of it.

Usage: bench/robustness/interruptions.py --qdmeta BIN [--quick] [--work DIR] [--timeout S]

Three families of cases, each judged on what the program does, never on timing (a run is stopped
by its own test hook, QDMETA_TEST_SIGNAL_AT_CHECKPOINT, or by the file size limit):

  rerun    an experiment (3 replicates of MAP-Elites) stopped after seed 1, then changed (its
           config edited, a `set` added, the budget changed, a plan row of another config) and run
           again: fine when refused in one line naming the changed key, nothing written; then
           --restart-changed must leave every replicate with one config fingerprint.
  link     a QD-Meta run interrupted at its first checkpoint, one of its files replaced by a
           symbolic link to a copy: `resume` must refuse in one line and change no file, or
           finish to the bits of an uninterrupted run.
  fsize    a run under `ulimit -f` of several sizes: exit 0, or exit 2 in one line with no
           temporary left; then `resume` without the limit must finish to the uninterrupted bits.

Prints one line per defect, then `N cases, M defects`; exits 1 when there is a defect. --quick: a
reduced matrix for the test suite (ctest robustness_interruptions). Plain python3.
"""
import filecmp
import os
import re
import shutil
import subprocess
import sys

import matrix

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PREFIX = "qdmeta: error:"
QD_META = ('algorithm = "qd-meta"\n[budget]\nevaluations = 600_000\n[checkpoint]\nevery_seconds = 1e9\n'
           "[qd_meta]\ndatabase_capacity = 100_000\n")
MAP_ELITES = 'algorithm = "map-elites"\n[budget]\nevaluations = {evals}\n[checkpoint]\nevery_seconds = 0\n'
OUTPUTS = ["metrics.csv", "meta.csv", "archive.csv"]


def run(argv, timeout, env=None, limit_kib=None):
    """(exit status or None on a timeout, output)."""
    if limit_kib is not None:  # bash's ulimit -f counts KiB
        argv = ["bash", "-c", f"ulimit -f {limit_kib}; exec \"$@\"", "bash"] + argv
    try:
        p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL,
                           env=env, timeout=timeout)
        return p.returncode, p.stdout.decode("utf-8", "replace")
    except subprocess.TimeoutExpired as e:
        return None, (e.output or b"").decode("utf-8", "replace")


def one_line_error(status, output):
    """None when the outcome is one qdmeta error line and exit 2, else what is wrong."""
    lines = output.splitlines()
    if status is None:
        return "hang (timeout)"
    if status != 2:
        return f"exit status {status}"
    if len(lines) != 1 or not lines[0].startswith(PREFIX):
        return f"{len(lines)} lines" if len(lines) != 1 else "not a qdmeta error line"
    return None


def snapshot(directory):
    """Every entry under `directory`: a file's bytes, a link's target."""
    out = {}
    for parent, _, names in os.walk(directory):
        for name in names:
            path = os.path.join(parent, name)
            rel = os.path.relpath(path, directory)
            if os.path.islink(path):
                out[rel] = "link " + os.readlink(path)
            else:
                with open(path, "rb") as f:
                    out[rel] = f.read()
    return out


def same_outputs(a, b):
    return all(filecmp.cmp(os.path.join(a, f), os.path.join(b, f), shallow=False)
               for f in OUTPUTS if os.path.exists(os.path.join(a, f)))


def temporaries(directory):
    return [n for n in os.listdir(directory) if re.search(r"\.tmp-\d+-\d+$", n)]


def rerun_cases(binary, work, timeout, quick):
    """(case name, defect or None) for each change to an experiment stopped after seed 1."""
    edits = [("config edited", "sigma = 0.2", "", [], "mutation.sigma"),
             ("set added", "sigma = 0.05", "set = { mutation = { sigma = 0.3 } }\n", [], "mutation.sigma"),
             ("budget changed", "sigma = 0.05", "", ["--evals", "30000"], "budget")]
    if not quick:
        edits.append(("plan row", "sigma = 0.2", "", ["--plan"], "mutation.sigma"))
    for name, sigma, experiment_set, extra, key in edits:
        d = os.path.join(work, "rerun-" + name.replace(" ", "-"))
        os.makedirs(d)
        config, experiment, out = os.path.join(d, "me.toml"), os.path.join(d, "experiment.toml"), os.path.join(d, "out")

        def write(sigma_line, set_line):
            with open(config, "w") as f:
                f.write(f'algorithm = "map-elites"\n[mutation]\n{sigma_line}\n')
            with open(experiment, "w") as f:
                f.write('name = "rerun"\nreplicates = 3\ntests = []\n[[condition]]\nname = "ME"\nconfig = "me.toml"\n'
                        + set_line)

        def experiment_call(args, evals="20000"):
            return [binary, "experiment", "--config", experiment, "--out", out, "--evals", evals, "--quiet",
                    "--no-report", "--threads", "1"] + args

        write("sigma = 0.05", "")
        first = ["--plan"] if extra == ["--plan"] else ["--seeds", "1"]
        status, output = run(experiment_call(first), timeout)
        if status != 0:
            yield name, f"the first call failed ({status}): {output.strip()[:200]}"
            continue
        write(sigma, experiment_set)
        before = snapshot(out)
        again = experiment_call([], extra[1]) if extra[:1] == ["--evals"] else experiment_call(extra)
        status, output = run(again, timeout)
        wrong = one_line_error(status, output)
        if not wrong and key not in output:
            wrong = f"the refusal does not name {key}: {output.strip()[:200]}"
        if not wrong and snapshot(out) != before:
            wrong = "the refused call changed the experiment's files"
        yield name, wrong
        status, output = run(again + ["--restart-changed"], timeout)
        if status != 0:
            yield name + ", restarted", f"exit status {status}: {output.strip()[:200]}"
            continue
        fingerprints = set()
        for r in (1, 2, 3):
            path = os.path.join(out, "me", f"seed-{r}", "config.toml")
            if os.path.exists(path):
                with open(path) as f:
                    fingerprints.update(re.findall(r"config_fingerprint = '([0-9a-f]+)'", f.read()))
        yield name + ", restarted", None if len(fingerprints) <= 1 else f"{len(fingerprints)} configs among the seeds"


def interrupted_run(binary, directory, timeout):
    config = directory + ".toml"
    with open(config, "w") as f:
        f.write(QD_META)
    env = dict(os.environ, QDMETA_TEST_SIGNAL_AT_CHECKPOINT="1:INT")
    status, output = run([binary, "run", "--config", config, "--out", directory, "--quiet", "--threads", "1"],
                         timeout, env)
    if status != 130:
        raise SystemExit(f"interruptions: the run to interrupt ended with {status}: {output.strip()[:200]}")
    return config


def link_cases(binary, work, timeout, quick):
    """(case name, defect or None) for each run file replaced by a link to its copy before resume."""
    base = os.path.join(work, "interrupted")
    config = interrupted_run(binary, base, timeout)
    straight = os.path.join(work, "straight")
    status, output = run([binary, "run", "--config", config, "--out", straight, "--quiet", "--threads", "1"], timeout)
    if status != 0:
        raise SystemExit(f"interruptions: the uninterrupted run failed ({status}): {output.strip()[:200]}")
    files = ["metrics.csv", "meta.csv"] if quick else sorted(os.listdir(base))
    for name in files:
        for target in ("relative", "absolute"):
            d = os.path.join(work, f"link-{name}-{target}")
            shutil.copytree(base, d, symlinks=True)
            copy = os.path.join(d, name + ".copy")
            shutil.copyfile(os.path.join(d, name), copy)
            os.unlink(os.path.join(d, name))
            os.symlink(os.path.basename(copy) if target == "relative" else copy, os.path.join(d, name))
            before = snapshot(d)
            status, output = run([binary, "resume", "--out", d, "--quiet", "--threads", "1"], timeout)
            if status == 0:
                wrong = None if same_outputs(straight, d) else "resumed to other bits"
            else:
                wrong = one_line_error(status, output) or (
                    "the refused resume changed the directory" if snapshot(d) != before else None)
            yield f"{name} ({target} link)", wrong
            if quick:
                break


def fsize_cases(binary, work, timeout, quick):
    """(case name, defect or None) for a run under each file size limit, then resumed without it."""
    config = os.path.join(work, "fsize.toml")
    with open(config, "w") as f:
        f.write(MAP_ELITES.format(evals="300_000"))
    straight = os.path.join(work, "fsize-straight")
    status, output = run([binary, "run", "--config", config, "--out", straight, "--quiet", "--threads", "1"], timeout)
    if status != 0:
        raise SystemExit(f"interruptions: the uninterrupted run failed ({status}): {output.strip()[:200]}")
    for kib in ([1500] if quick else [20, 200, 600, 1000, 1500, 2000, 4000]):
        d = os.path.join(work, f"fsize-{kib}")
        status, output = run([binary, "run", "--config", config, "--out", d, "--quiet", "--threads", "1"], timeout,
                             limit_kib=kib)
        wrong = None if status == 0 else one_line_error(status, output)
        if not wrong and os.path.isdir(d) and temporaries(d):
            wrong = f"left {', '.join(temporaries(d))}"
        if not wrong and status != 0:
            if os.path.exists(os.path.join(d, "checkpoint.bin")):
                status, output = run([binary, "resume", "--out", d, "--quiet", "--threads", "1"], timeout)
            else:  # stopped before its first checkpoint: it starts over
                status, output = run([binary, "run", "--config", config, "--out", d, "--quiet", "--threads", "1",
                                      "--overwrite"], timeout)
            if status != 0:
                wrong = f"the resume failed ({status}): {output.strip()[:200]}"
            elif not same_outputs(straight, d):
                wrong = "resumed to other bits"
        yield f"ulimit -f {kib}", wrong


def main(argv):
    args = matrix.argument_parser(__doc__, "a reduced matrix (the test suite's)", timeout=120).parse_args(argv[1:])
    binary = os.path.abspath(args.qdmeta)
    with matrix.work_folder(args.work, "qdmeta-interruptions-") as work:
        cases = defects = 0
        for family, cases_of in (("rerun", rerun_cases), ("link", link_cases), ("fsize", fsize_cases)):
            family_work = os.path.join(work, family)
            shutil.rmtree(family_work, ignore_errors=True)
            os.makedirs(family_work)
            for name, wrong in cases_of(binary, family_work, args.timeout, args.quick):
                cases += 1
                if wrong:
                    defects += 1
                    print(f"DEFECT {family} {name}: {wrong}", flush=True)
        return matrix.verdict(cases, defects)

if __name__ == "__main__":
    sys.exit(main(sys.argv))
