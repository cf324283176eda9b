"""Ctrl-C in every long Python call: a real SIGINT to a child process running an ensemble (of a
model and of a typed Lagrangian), a section, varsym.call and varsym.run with a tool option.
Each must raise varsym.Interrupted within 0.2 s of the signal, keeping what was computed. (They
ran to the end, 21.5 s after the signal on a 21.9 s ensemble, and discarded the results.)"""

import os
import signal
import subprocess
import sys
import time

import pytest

CHILD = """
import os, sys, time, numpy as np, varsym
what, scratch = sys.argv[1], sys.argv[2]
print("ready", flush=True)
try:
    if what == "ensemble":
        varsym.Model("henon-heiles").ensemble({"energy": np.full(6, 0.1)}, t_span=1e6,
                                               steps=10**8, threads=2)
    elif what == "lagrangian-ensemble":
        varsym.Lagrangian("0.5*q_dot**2 - 0.5*q**2", coordinates="q").ensemble(
            q0=np.ones((4, 1)), p0=np.zeros((4, 1)), t_span=1e6, steps=10**9, threads=2)
    elif what == "section":
        varsym.Model("henon-heiles").stepper(h=0.01).section(steps=10**11, crossings=10**10)
    elif what == "call":
        varsym.call(["run", "--model", "pendulum", "--time", "1e6", "--steps", "300000000",
                     "--every", "1000", "-o", os.path.join(scratch, "call.csv"), "--quiet"])
    elif what == "run":
        varsym.run("pendulum", time=1e6, steps=300000000, every=1000, newton_tol=1e-12)
except varsym.Interrupted as e:
    caught = time.time()
    p = e.partial
    if what.endswith("ensemble"):
        kept = sum(s == "completed" for s in p["status"]), sorted(set(p["status"]))
    elif what == "section":
        kept = len(p[0]), p[1].shape
    elif what == "call":
        kept = sorted(os.listdir(scratch))
    else:
        kept = len(p), p.t[-1] > 0
    print(caught, repr(kept), flush=True)
    sys.exit(7)
print("finished without an interrupt", flush=True)
"""

EXPECTED = {
    # Every member was in flight (2 threads) or waiting: none completed, none lost silently.
    "ensemble": lambda kept: kept[0] == 0 and "stopped" in kept[1] and "not run" in kept[1],
    "lagrangian-ensemble": lambda kept: kept[0] == 0 and "stopped" in kept[1],
    "section": lambda kept: kept[0] > 0 and kept[1] == (kept[0], 4),
    # The tool's own stop: its rows in FILE.part and a checkpoint to resume from.
    "call": lambda kept: kept == ["call.csv.ckpt", "call.csv.part"],
    "run": lambda kept: kept[0] > 1 and kept[1],
}


@pytest.mark.parametrize("what", list(EXPECTED))
def test_sigint_stops_the_call_within_0_2_s_keeping_what_was_computed(what, tmp_path):
    child = subprocess.Popen([sys.executable, "-c", CHILD, what, str(tmp_path)],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                             env={**os.environ})
    assert child.stdout.readline().strip() == "ready"
    time.sleep(1.5)
    sent = time.time()
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=60)
    assert child.returncode == 7, out + err
    caught, kept = out.split(" ", 1)
    print(f"{what}: Interrupted {float(caught) - sent:.3f} s after SIGINT")
    assert float(caught) - sent < 0.2, f"{what}: Interrupted {float(caught) - sent:.3f} s late"
    assert EXPECTED[what](eval(kept)), f"{what}: kept {kept}"  # noqa: S307 (our own repr)
