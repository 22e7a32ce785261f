"""Threads solving at once under an address-space limit: each solve returns the answer of a
single-threaded solve or raises the library's error naming the limit; the interpreter never
aborts. (Each thread that multiplies dense matrices keeps the kernels' workspace, two buffers
the size of the last-level cache; under `ulimit -v` the third or fourth thread used to fail
that allocation and abort the process.)"""
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import mlpg_contact as mc

ROOT = Path(__file__).resolve().parents[2]
PROBLEM = ROOT / "problems" / "two_blocks.toml"

CHILD = r"""
import json, resource, sys, threading
import numpy as np
import mlpg_contact as mc

def mapped():
    for line in open("/proc/self/status"):
        if line.startswith("VmSize:"):
            return int(line.split()[1]) * 1024

problem, margins = sys.argv[1], json.loads(sys.argv[2])
start = mapped()
rounds = []
for margin in margins:
    # The soft limit only (the hard one stays), so that each round sets its own.
    hard = resource.getrlimit(resource.RLIMIT_AS)[1]
    resource.setrlimit(resource.RLIMIT_AS, (start + margin, hard))
    out = [None] * 4
    def run(i):
        try:
            out[i] = ["ok", mc.solve(problem).displacement.tolist()]
        except (mc.ProblemError, mc.SolveError) as e:
            out[i] = [type(e).__name__, str(e)]
        except BaseException as e:
            out[i] = ["other " + type(e).__name__, str(e)]
    threads = [threading.Thread(target=run, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    rounds.append(out)
print(json.dumps(rounds))
"""


def test_four_threads_under_an_address_space_limit_answer_or_refuse():
    expected = mc.solve(PROBLEM).displacement
    # 0.64 GB above what the child maps after its imports: one two-block solve fits (0.5 GB of
    # it is kept for stacks and arenas), four at once do not (the case that aborted); 1.3 GB:
    # some fit.
    margins = [1_300_000_000, 640_000_000]
    child = subprocess.run(
        [sys.executable, "-c", CHILD, str(PROBLEM), json.dumps(margins)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert child.returncode == 0, f"the child ended with {child.returncode}: {child.stderr[-2000:]}"
    rounds = json.loads(child.stdout)
    assert len(rounds) == len(margins)
    for margin, out in zip(margins, rounds):
        for kind, value in out:
            if kind == "ok":
                assert np.array_equal(np.array(value), expected), margin
            else:
                assert kind == "SolveError", (margin, kind, value)
                assert "limit" in value and "needs about" in value, value
    # The first round leaves room for at least one solve.
    assert any(kind == "ok" for kind, _ in rounds[0]), rounds[0]
