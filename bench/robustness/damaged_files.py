#!/usr/bin/python3
"""The damaged-file matrix: every file of a small experiment, damaged one way at a time, read by
`qdmeta report`, `resume` and `adapt`.

Usage: bench/robustness/damaged_files.py --qdmeta BIN [--commands report,resume,adapt] [--quick]
                                         [--work DIR] [--timeout S] [--tools DIR]

Makes a small experiment with BIN (2 conditions x 1 replicate of 20,000 evaluations, the
dimension test; planned first, so plan.tsv and condition.toml exist) and, for resume, a QD-Meta
run interrupted after its first checkpoint. Then, for each file, each damage and each command
that reads the file, damages the file in a fresh copy and runs the command with a timeout.
An outcome is fine when the command exits 0, or exits 2 printing exactly one line that starts
`qdmeta: error:`; anything else is a defect: a traceback, a signal, a hang (the timeout), memory
exhausted (each command runs under a 4 GiB address-space limit, so /dev/zero cannot take the
machine), several lines, another exit status. Prints one line per defect, then
`N cases, M defects`; exits 1 when there is a defect.

--quick: a reduced matrix for the test suite (ctest robustness_damaged_files_report runs it for
report). Plain python3, no third-party package.
"""
import os
import resource
import shutil
import signal
import subprocess
import sys
import time

import matrix

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MEMORY_LIMIT = 4 << 30
PREFIX = "qdmeta: error:"

QD_META_CONFIG = ('algorithm = "qd-meta"\n[budget]\nevaluations = {evals}\n[checkpoint]\nevery_seconds = 0.1\n'
                  "[qd_meta]\ndatabase_capacity = 100_000\n")
EXPERIMENT = """name = "damaged files"
replicates = 1
tests = ["dimension"]
[[condition]]
name = "QD-Meta"
config = "qd-meta.toml"
[[condition]]
name = "ME"
config = "{map_elites}"
[[claim]]
text = "ME stays under a billion elites"
kind = "below"
measure = "population:num_elites"
conditions = ["ME"]
value = 1e9
"""


def damage(path, how):
    """Damages the file at `path` one way."""
    if how.startswith("truncate-"):
        size = os.path.getsize(path)
        os.truncate(path, size * int(how.split("-")[1]) // 100)
        return
    if how in ("flip", "flip-low-bit", "nul"):  # the middle byte: inverted, its lowest bit flipped, or NUL
        with open(path, "r+b") as f:
            data = bytearray(f.read())
            middle = len(data) // 2
            data[middle] = {"flip": data[middle] ^ 0xFF, "flip-low-bit": data[middle] ^ 0x01, "nul": 0}[how]
            f.seek(0)
            f.write(data)
        return
    if how == "garbage":
        with open(path, "ab") as f:
            f.write(b'garbage,1e999,,"\n[[x = \n')
        return
    os.unlink(path)
    if how == "directory":
        os.mkdir(path)
    elif how == "fifo":
        os.mkfifo(path)
    elif how == "dev-zero":
        os.symlink("/dev/zero", path)
    elif how == "dangling":
        os.symlink(path + ".nowhere", path)
    elif how != "remove":
        raise ValueError(how)


DAMAGES = ["truncate-0", "truncate-50", "truncate-95", "flip", "flip-low-bit", "garbage", "nul", "directory", "fifo",
           "dev-zero", "dangling", "remove"]
QUICK_DAMAGES = ["truncate-50", "flip", "nul", "fifo", "dev-zero"]
QUICK_FILES = ["experiment.toml", "qd-meta/seed-1/summary.json", "qd-meta/seed-1/archive.csv",
               "qd-meta/seed-1/metrics.csv", "qd-meta/seed-1/meta.csv", "me/seed-1/adapt-dimension.csv",
               "me/seed-1/config.toml"]


def readers(relative, interrupted):
    """The commands that read a file: report reads the whole experiment, resume a run's state and
    logs, adapt a finished run's config, summary and archive (and rewrites its adapt-*.csv)."""
    name = os.path.basename(relative)
    if interrupted:
        return ["resume", "adapt"]
    if relative.count("/") < 2:  # experiment.toml, plan.tsv, <condition>/condition.toml
        return ["report"]
    out = ["report"]
    if not name.startswith("adapt-"):
        out.append("resume")
    if name in ("config.toml", "summary.json", "archive.csv", "checkpoint.bin") or name.startswith("adapt-"):
        out.append("adapt")
    return out


def limit_memory():
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def run(argv, timeout, env):
    """(exit status or None on a timeout, output): stdout and stderr together."""
    p = subprocess.Popen(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL, env=env,
                         start_new_session=True, preexec_fn=limit_memory)
    try:
        out, _ = p.communicate(timeout=timeout)
        return p.returncode, out.decode("utf-8", "replace")
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        return None, out.decode("utf-8", "replace")


def classify(status, output):
    """None when fine, else what is wrong."""
    lines = output.splitlines()
    if status is None:
        return "hang (timeout)"
    if status < 0 or status >= 128:
        return f"signal {-status if status < 0 else status - 128}"
    if "Traceback (most recent call last)" in output:
        return "traceback"
    if "out of memory" in output or "MemoryError" in output or "bad_alloc" in output:
        return "memory exhausted"
    if status == 0:
        return None
    if status != 2:
        return f"exit status {status}"
    if len(lines) != 1:
        return f"{len(lines)} lines"
    if not lines[0].startswith(PREFIX):
        return "not a qdmeta error line"
    return None


def command_line(binary, command, experiment, run_dir):
    if command == "report":
        return [binary, "report", experiment, "--quiet"]
    if command == "resume":
        return [binary, "resume", "--out", run_dir, "--threads", "1", "--quiet"]
    return [binary, "adapt", "--run", run_dir, "--test", "dimension", "--threads", "1", "--quiet"]


def make_experiment(binary, work, env, interrupt):
    """The undamaged experiment (work/base), its report checked, and with `interrupt` a run
    interrupted after its first checkpoint (work/interrupted; None when it finished first)."""
    base = os.path.join(work, "base")
    config = os.path.join(work, "config")
    os.makedirs(config)
    with open(os.path.join(config, "qd-meta.toml"), "w") as f:
        f.write(QD_META_CONFIG.format(evals="500_000"))
    experiment = os.path.join(config, "experiment.toml")
    with open(experiment, "w") as f:
        f.write(EXPERIMENT.format(map_elites=os.path.join(ROOT, "configs/rastrigin/map-elites.toml")))
    for extra in (["--plan"], ["--no-report"]):
        status, out = run([binary, "experiment", "--config", experiment, "--out", base, "--evals", "20000", "--quiet",
                           "--threads", "1"] + extra, 300, env)
        if status != 0:
            raise SystemExit(f"damaged_files: the undamaged experiment failed ({status}): {out}")
    status, out = run([binary, "report", base, "--quiet"], 120, env)
    if status != 0:
        raise SystemExit(f"damaged_files: the report of the undamaged experiment failed ({status}): {out}")
    if not interrupt:
        return base, None

    # A run interrupted after a checkpoint: what resume reads when there is something to resume.
    interrupted = os.path.join(work, "interrupted")
    with open(os.path.join(config, "long.toml"), "w") as f:
        f.write(QD_META_CONFIG.format(evals="600_000"))
    p = subprocess.Popen([binary, "run", "--config", os.path.join(config, "long.toml"), "--out", interrupted,
                          "--quiet", "--threads", "1"], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env)
    deadline = time.monotonic() + 60
    while not os.path.exists(os.path.join(interrupted, "checkpoint.bin")) and time.monotonic() < deadline:
        time.sleep(0.02)
    p.send_signal(signal.SIGINT)
    p.wait()
    if not os.path.exists(os.path.join(interrupted, "checkpoint.bin")):  # a finished run keeps none
        shutil.rmtree(interrupted, ignore_errors=True)
        print("damaged_files: no interrupted run (it finished before the signal): resume's checkpoint cases left out")
        return base, None
    return base, interrupted


def files_of(directory):
    out = []
    for parent, dirs, names in os.walk(directory):
        dirs[:] = [d for d in dirs if d not in ("figures", "data")]  # the report's outputs
        for name in names:
            if name != "report.md":
                out.append(os.path.relpath(os.path.join(parent, name), directory))
    return sorted(out)


def main(argv):
    parser = matrix.argument_parser(__doc__, "a reduced matrix (the test suite's)", timeout=30)
    parser.add_argument("--commands", default="report,resume,adapt", help="of report, resume, adapt")
    parser.add_argument("--tools", help="QDMETA_TOOLS_DIR for the report (default: the binary's own)")
    args = parser.parse_args(argv[1:])
    commands = args.commands.split(",")
    if not commands or any(c not in ("report", "resume", "adapt") for c in commands):
        parser.error("--commands takes a comma-separated list of report, resume, adapt")
    binary = os.path.abspath(args.qdmeta)
    env = dict(os.environ)
    if args.tools:
        env["QDMETA_TOOLS_DIR"] = os.path.abspath(args.tools)
    with matrix.work_folder(args.work, "qdmeta-damaged-") as work:
        interrupt = not args.quick and ("resume" in commands or "adapt" in commands)
        base, interrupted = make_experiment(binary, os.path.join(work, f"m{os.getpid()}"), env, interrupt)
        sources = [(base, False)] + ([(interrupted, True)] if interrupted else [])
        cases = defects = exit_zero = 0
        scratch = os.path.join(os.path.dirname(base), "case")
        for source, is_interrupted in sources:
            files = QUICK_FILES if args.quick else files_of(source)
            for relative in files:
                for how in QUICK_DAMAGES if args.quick else DAMAGES:
                    for command in readers(relative, is_interrupted):
                        if command not in commands:
                            continue
                        shutil.rmtree(scratch, ignore_errors=True)
                        shutil.copytree(source, scratch, symlinks=True)
                        damage(os.path.join(scratch, relative), how)
                        run_dir = scratch if is_interrupted else os.path.join(scratch, os.path.dirname(relative))
                        status, output = run(command_line(binary, command, scratch, run_dir), args.timeout, env)
                        cases += 1
                        wrong = classify(status, output)
                        exit_zero += status == 0
                        if wrong:
                            defects += 1
                            last = output.strip().splitlines()[-1] if output.strip() else ""
                            where = ("interrupted/" if is_interrupted else "") + relative
                            print(f"DEFECT {command} {where} {how}: {wrong}: {last[:200]}", flush=True)
        shutil.rmtree(scratch, ignore_errors=True)
        print(f"fine: {exit_zero} exit 0, {cases - defects - exit_zero} one-line errors")
        return matrix.verdict(cases, defects)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
