"""Prints the active emitters of pyribs's BanditScheduler, ask by ask, for the scripted successes
and restarts that tests/emitters/emitter_bandit_test.cpp replays (kPyribsActive there).

Run with pyribs 0.12.0 installed (the version bench/peers pins):
    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    /tmp/ribs/bin/python tests/emitters/pyribs_reference/make_bandit_reference.py

The emitters are stand-ins that ask for ROWS rows and restart when the script says; after each
ask the script does what BanditScheduler.tell does to its counts (selection += rows, success +=
the scripted successes), so the archive plays no part.
"""
import warnings

import numpy as np
from ribs.archives import GridArchive
from ribs.schedulers import BanditScheduler

POOL, ROWS, ASKS = 5, 10, 12


class StandIn:
    def __init__(self, restarts):
        self.solution_dim, self.restarts, self.has_runs = 2, 0, restarts

    def ask(self):
        return np.zeros((ROWS, 2))


def successes(step, i):
    return (3 * i + 7 * step) % 11 if (i + step) % 3 else 0


def restarts(step, i):
    return (step + i) % 4 == 0


def run(num_active, reselect, zeta, with_runs):
    archive = GridArchive(solution_dim=2, dims=[2], ranges=[(0, 1)])
    pool = [StandIn(with_runs) for _ in range(POOL)]
    if not with_runs:
        for e in pool:
            del e.restarts
    s = BanditScheduler(archive, pool, num_active=num_active, reselect=reselect, zeta=zeta)
    out = []
    for step in range(ASKS):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # ln 0 while nothing has succeeded: NaN, as the test expects
            s.ask()
        out.append([int(i) for i in np.where(s.active)[0]])
        s._last_called = "tell"  # pylint: disable = protected-access
        for i in np.where(s.active)[0]:
            s._selection[i] += ROWS  # pylint: disable = protected-access
            s._success[i] += min(ROWS, successes(step, i))  # pylint: disable = protected-access
            if with_runs and restarts(step, i):
                pool[i].restarts += 1
    return out


for args in [(2, "all", 0.05, False), (2, "terminated", 0.05, True), (3, "terminated", 1.0, False),
             (1, "all", 2.0, False)]:
    print(args, run(*args))
