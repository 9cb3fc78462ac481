#!/usr/bin/env python3
"""Where ctest's time goes: reads a LastTest.log (build/Testing/Temporary/) and prints the wall
time of that ctest, the test-seconds of the long tests (label "long": `make test-long`) and of the
rest (`make test`), and the slowest tests. Which tests are long is read from tests/CMakeLists.txt
(the binaries in qdmeta_long_test_binaries, the tests whose LABELS name "long"), so that a log of
a build made before the labels existed is split the same way.
Usage: scripts/test-times.py [LastTest.log] [--top N]"""
import argparse
import pathlib
import re

ROOT = pathlib.Path(__file__).resolve().parent.parent


def long_tests():
    text = (ROOT / "tests" / "CMakeLists.txt").read_text()
    binaries = re.search(r"set\(qdmeta_long_test_binaries ([^)]*)\)", text).group(1).split()
    scripts = re.findall(r"set_tests_properties\((\S+) PROPERTIES LABELS \"[^\"]*\blong\b", text)
    return set(binaries), set(scripts)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("log", nargs="?", default="build/Testing/Temporary/LastTest.log")
    parser.add_argument("--top", type=int, default=15)
    args = parser.parse_args()
    text = pathlib.Path(args.log).read_text(errors="replace")
    # Each test's block: "N/M Testing: NAME", its "Command: ...", and later "Test time =  X sec".
    entries = []
    for block in re.split(r"^(?=\d+/\d+ Testing: )", text, flags=re.M)[1:]:
        name = block.split("\n", 1)[0].split("Testing: ", 1)[1].strip()
        command = re.search(r"^Command: (.*)$", block, flags=re.M)
        seconds = re.search(r"Test time =\s+([\d.]+) sec", block)
        if command and seconds:
            entries.append((name, command.group(1), seconds.group(1)))
    binaries, scripts = long_tests()
    split = {True: [], False: []}
    for name, command, seconds in entries:
        program = pathlib.Path(command.split('"')[1]).name if command.startswith('"') else ""
        split[name in scripts or program in binaries].append((float(seconds), name))
    start = re.search(r"^Start testing: (.*)$", text, flags=re.M)
    end = re.search(r"^End testing: (.*)$", text, flags=re.M)
    if start and end:
        print(f"ctest ran from {start.group(1)} to {end.group(1)}")
    for is_long, label in ((False, "make test (ctest -LE long)"), (True, "make test-long (ctest -L long)")):
        tests = split[is_long]
        print(f"{label}: {len(tests)} tests, {sum(t for t, _ in tests):.0f} test-seconds")
    print(f"slowest {args.top}:")
    for seconds, name in sorted(split[True] + split[False], reverse=True)[: args.top]:
        print(f"  {seconds:7.1f} s  {name}{'  (long)' if (seconds, name) in split[True] else ''}")


if __name__ == "__main__":
    main()
