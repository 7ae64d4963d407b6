"""Ctrl-C, progress and the GIL during a solve."""
import _thread
import threading
import time

import pytest

import cmcsurf


def test_keyboard_interrupt_stops_a_64_run_within_a_second():
    fired = []

    def interrupt():
        fired.append(time.perf_counter())
        _thread.interrupt_main()  # as Ctrl-C: SIGINT's handler runs in the main thread

    timer = threading.Timer(0.5, interrupt)
    steps = []
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # The paper's path: the fast mode ends a 64^3 run before the timer fires.
            cmcsurf.run("G", 0.5, 64, threads=1, paper=True, progress=steps.append)
        stopped = time.perf_counter()
    finally:
        timer.cancel()
    assert fired and stopped - fired[0] < 1.0
    assert steps  # it was running, not refused at the start
    # The interpreter and the module are intact: another run works.
    r = cmcsurf.run("sphere", grid=16, epsilon=0.05, max_steps=3, threads=1)
    assert r.report["steps"] == 3


def interrupt_from_a_thread(fired):
    """Ctrl-C as a second thread gives it: SIGINT's handler then runs in the main thread."""
    def fire():
        fired.append(time.perf_counter())
        _thread.interrupt_main()
    threading.Thread(target=fire).start()


def test_keyboard_interrupt_stops_a_sweep_in_its_second_member():
    fired, members = [], []

    def progress(d):
        members.append(d["member"])
        if d["member"] == "G_0.50" and d["step"] == 3 and not fired:
            interrupt_from_a_thread(fired)

    with pytest.raises(KeyboardInterrupt):
        cmcsurf.sweep(("G",), (0.4, 0.5), grid=32, fast=True, threads=1, progress=progress)
    stopped = time.perf_counter()
    assert fired and stopped - fired[0] < 1.0
    # It stopped in the second member, before that member's end: far fewer steps than the first.
    assert members[0] == "G_0.40" and members[-1] == "G_0.50"
    assert members.count("G_0.50") < members.count("G_0.40") / 2
    r = cmcsurf.run("sphere", grid=16, epsilon=0.05, max_steps=3, threads=1)
    assert r.report["steps"] == 3


def test_keyboard_interrupt_stops_relax():
    fired, steps = [], []

    def progress(d):
        steps.append(d["step"])
        if len(steps) == 5:
            interrupt_from_a_thread(fired)

    phi = cmcsurf.initial_field("G", 32)
    with pytest.raises(KeyboardInterrupt):
        cmcsurf.relax(phi, 0.4, threads=1, progress=progress)
    stopped = time.perf_counter()
    assert fired and stopped - fired[0] < 1.0
    # The whole relaxation takes well over a hundred steps; it stopped within a few of the fifth.
    assert 5 <= len(steps) <= 10
    assert cmcsurf.relax(phi, 0.4, epsilon=0.05, max_steps=2, threads=1).report["steps"] >= 1


def test_progress_gets_a_dict_per_step():
    records = []
    r = cmcsurf.run("G", 0.5, 16, epsilon=0.05, threads=1, progress=records.append)
    h = r.history
    assert len(records) == len(h["step"]) > 5
    assert [d["step"] for d in records] == list(h["step"])
    assert records[0]["stage"] == "prerelax" and records[-1]["area"] == h["area"][-1]
    assert set(records[0]) == {"step", "stage", "time", "dt", "area", "d_area", "d_phi",
                               "energy", "mass", "vcycles", "residual", "elapsed",
                               "volume_fraction", "equilibrium_residual"}


def test_an_exception_in_progress_stops_the_run_and_propagates():
    calls = []

    def progress(d):
        calls.append(d)
        if len(calls) == 3:
            raise ZeroDivisionError("from progress")

    with pytest.raises(ZeroDivisionError, match="from progress"):
        cmcsurf.run("sphere", grid=16, epsilon=0.05, threads=1, progress=progress)
    assert len(calls) == 3


def test_other_threads_run_during_a_solve():
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(1)
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        start = time.perf_counter()
        cmcsurf.run("G", 0.5, 32, threads=1, max_steps=40)
        seconds = time.perf_counter() - start
    finally:
        done.set()
        t.join()
    # With the GIL held for the whole solve the ticker would get nothing in between.
    assert len(ticks) > 0.2 * seconds / 0.001 * 0.5
