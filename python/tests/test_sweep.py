"""sweep() against `cmcsurf sweep`: the same members, reports and table."""
import csv
import json

import numpy as np
import pytest

import cmcsurf
from conftest import comparable, load_report, page_flags, run_cli, volatile


def test_sweep_equals_cli_sweep(tmp_path):
    steps = []
    # epsilon 0.03: at 0.05 on 16^3, D at 0.45 dissolves into one phase (no surface: an error)
    results, table = cmcsurf.sweep(("P", "D"), (0.45, 0.5), grid=16, epsilon=0.03,
                                   continuation=True, threads=1, progress=steps.append)
    out = tmp_path / "sweep"
    run_cli("sweep", "--surface", "P,D", "--volume-fractions", "0.45,0.5", "--grid", "16",
            "--epsilon", "0.03", "--continuation", "--threads", "1", "--quiet", "--no-plot",
            *page_flags(), "--out", str(out))
    names = [r.report["member"] for r in results]
    assert names == ["P_0.45", "P_0.50", "D_0.45", "D_0.50"]
    assert results[1].report["started_from"] == "P_0.45"
    for r in results:
        # The member's report.json adds the time of its writes, which Result.save() times.
        cli = load_report(out / r.report["member"])
        assert cli.pop("write_seconds") >= 0
        assert comparable(r.report) == comparable(cli)
        # Each member's steps, in order, with the member's name in the progress dicts.
        ours = [d["step"] for d in steps if d["member"] == r.report["member"]]
        assert ours == list(r.history["step"])
    assert [d["member"] for d in steps] == \
        [r.report["member"] for r in results for _ in r.history["step"]]
    with open(out / "sweep.csv", newline="") as f:
        header = next(csv.reader(f))
    assert list(table) == [h for h in header if h != "write_seconds"]  # the CLI's writes
    assert np.array_equal(table["area"], [r.report["area"] for r in results])
    assert list(table["surface"]) == ["P", "P", "D", "D"]


def test_sweep_refuses_bad_lists():
    import pytest
    with pytest.raises(ValueError, match="--volume-fractions"):
        cmcsurf.sweep(("P",), (0.5, 1.5), grid=16)
    with pytest.raises(ValueError, match="--surface"):
        cmcsurf.sweep(("sphere",), (0.5,), grid=16)


# The folder tests' sweep: two G members on 16^3 (6 and 67 steps), without the pictures,
# whose preview stage costs more than the members. No Anderson mixing: a checkpoint does not
# carry its history, so a member resumed mid-mixing would end on the same surface but not the
# same bits.
FOLDER = dict(surfaces="G", volume_fractions=(0.5, 0.45), grid=16, epsilon=0.05, max_steps=30,
              anderson_depth=0, threads=1)
FOLDER_CLI = ["sweep", "--surface", "G", "--volume-fractions", "0.5,0.45", "--grid", "16",
              "--epsilon", "0.05", "--max-steps", "30", "--anderson-depth", "0", "--threads", "1",
              "--quiet", "--no-preview", "--no-report", "--no-plot"]


MEMBERS = ("G_0.50", "G_0.45")


def _same_folders(a, b, members=MEMBERS):
    """Two sweep folders hold the same files, equal but for the volatile values (timings,
    memory): sweep.csv, sweep.json, and each member's report.json, history.csv (less its
    elapsed column) and field.vti, the last to the byte."""
    names = lambda d: sorted(p.name for p in d.iterdir() if not p.name.startswith("."))
    assert names(a) == names(b)
    ja, jb = (json.loads((d / "sweep.json").read_text()) for d in (a, b))
    assert comparable(ja) == comparable(jb)
    with open(a / "sweep.csv", newline="") as f, open(b / "sweep.csv", newline="") as g:
        ra, rb = list(csv.DictReader(f)), list(csv.DictReader(g))
    assert [list(r) for r in ra] == [list(r) for r in rb]
    for x, y in zip(ra, rb):
        assert {k: v for k, v in x.items() if not volatile(k)} == \
            {k: v for k, v in y.items() if not volatile(k)}
    for m in members:
        assert names(a / m) == names(b / m)
        assert comparable(load_report(a / m)) == comparable(load_report(b / m))
        assert (a / m / "field.vti").read_bytes() == (b / m / "field.vti").read_bytes()
        with open(a / m / "history.csv") as f, open(b / m / "history.csv") as g:
            ha, hb = f.read().splitlines(), g.read().splitlines()
        drop = ha[0].split(",").index("elapsed")
        strip = lambda rows: [[c for i, c in enumerate(r.split(",")) if i != drop] for r in rows]
        assert strip(ha) == strip(hb)


def test_sweep_out_writes_the_cli_folder(tmp_path):
    ours, cli = tmp_path / "py", tmp_path / "cli"
    results, table = cmcsurf.sweep(**FOLDER, out=ours, preview=False, report=False, plot=False)
    run_cli(*FOLDER_CLI, "--out", str(cli))
    _same_folders(ours, cli)
    # The Results are the members as written, and the table is sweep.csv's.
    assert [r.report for r in results] == [load_report(ours / m) for m in MEMBERS]
    with open(ours / "sweep.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert list(table) == list(rows[0])
    assert [float(r["area"]) for r in rows] == list(table["area"])
    assert np.array_equal(results[1].phi.shape, (16, 16, 16))
    # Into a folder that is someone else's: refused before any work, as --out is.
    other = tmp_path / "other"
    other.mkdir()
    (other / "notes.txt").write_text("mine")
    with pytest.raises(ValueError, match="out"):
        cmcsurf.sweep(**FOLDER, out=other)


def test_sweep_resume_continues_an_interrupted_folder(tmp_path):
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    cmcsurf.sweep(**FOLDER, out=whole, preview=False, report=False, plot=False)

    class Stop(Exception):
        pass

    def stop_in_second_member(d):
        if d["member"] == "G_0.45" and d["step"] == 20:
            raise Stop()

    with pytest.raises(Stop):
        cmcsurf.sweep(**FOLDER, out=stopped, preview=False, report=False, plot=False,
                      progress=stop_in_second_member)
    # The first member complete, the second interrupted with its checkpoint, as a signal
    # leaves a command line's sweep.
    assert load_report(stopped / "G_0.50")["stop_reason"] != "interrupted"
    left = load_report(stopped / "G_0.45")
    assert left["stop_reason"] == "interrupted"
    assert left["checkpoint"]["signal"] == "a Python exception in progress"
    assert (stopped / "G_0.45" / "checkpoint.bin").exists()
    assert json.loads((stopped / "sweep.json").read_text())["complete"] is False

    # Arguments given must agree with the sweep.
    with pytest.raises(ValueError, match="epsilon"):
        cmcsurf.sweep(resume=stopped, epsilon=0.04)
    with pytest.raises(ValueError, match="volume_fractions: differs"):
        cmcsurf.sweep(resume=stopped, volume_fractions=(0.45, 0.5))

    steps = []
    results, table = cmcsurf.sweep(resume=stopped, progress=steps.append)
    # The kept member is not run again; the table has both.
    assert [r.report["member"] for r in results] == ["G_0.45"]
    assert {d["member"] for d in steps} == {"G_0.45"} and steps[0]["step"] == 21
    assert list(table["member"]) == list(MEMBERS)
    summary = json.loads((stopped / "sweep.json").read_text())
    assert summary["resumed"] == {"members_kept": 1, "members_resumed": 1}
    del summary["resumed"]
    (stopped / "sweep.json").write_text(json.dumps(summary))
    _same_folders(stopped, whole)


def test_ctrl_c_leaves_a_folder_the_command_line_resumes(tmp_path):
    import _thread
    whole, stopped = tmp_path / "whole", tmp_path / "stopped"
    run_cli(*FOLDER_CLI, "--out", str(whole))

    def ctrl_c(d):  # SIGINT's handler, run at the sweep's next stop check
        if d["member"] == "G_0.45" and d["step"] == 20:
            _thread.interrupt_main()

    with pytest.raises(KeyboardInterrupt):
        cmcsurf.sweep(**FOLDER, out=stopped, preview=False, report=False, plot=False,
                      progress=ctrl_c)
    left = load_report(stopped / "G_0.45")
    assert left["checkpoint"]["signal"] == "SIGINT"
    assert left["resume"] == f"cmcsurf.sweep(resume={str(stopped)!r})"
    run_cli("sweep", "--resume", str(stopped), "--quiet")
    summary = json.loads((stopped / "sweep.json").read_text())
    assert summary.pop("resumed") == {"members_kept": 1, "members_resumed": 1}
    (stopped / "sweep.json").write_text(json.dumps(summary))
    _same_folders(stopped, whole)
