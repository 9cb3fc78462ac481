"""How the tools scripts that qdmeta runs end: a damaged input or an output they may not write
is one line "<script>: error: MESSAGE" and exit status 2 (qdmeta relays the line as its own); a
Ctrl-C is one line "<script>: interrupted" and exit status 130, as a shell reports SIGINT (qdmeta
passes 130 on), never a traceback.
"""
import os
import signal
import sys

from run_files import InputError

EXIT_BAD_INPUT = 2
EXIT_INTERRUPTED = 130


def _interrupted_line(name):
    print(f"{name}: interrupted", file=sys.stderr, flush=True)


def before_main(name):
    """Until main() runs (the imports: matplotlib's take a second), a Ctrl-C ends the script at
    once with its one line: nothing has been written yet."""
    def stop(signum, frame):
        _interrupted_line(name)
        os._exit(EXIT_INTERRUPTED)
    signal.signal(signal.SIGINT, stop)


def run(name, body):
    """body()'s exit status; an InputError or a Ctrl-C as the module says. The output files are
    written through temporary files renamed over their targets, so an interrupted script leaves
    each one whole, old or new."""
    signal.signal(signal.SIGINT, signal.default_int_handler)  # KeyboardInterrupt from here on
    try:
        return body()
    except InputError as e:
        # One line whatever the message holds (a directory name may hold a newline).
        line = str(e).replace("\r", "\\r").replace("\n", "\\n")
        print(f"{name}: error: {line}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except KeyboardInterrupt:
        _interrupted_line(name)
        return EXIT_INTERRUPTED
