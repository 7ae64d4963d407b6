"""sweep() against `cmcsurf sweep`: the same members, reports and table."""
import csv

import numpy as np

import cmcsurf
from conftest import comparable, load_report, page_flags, run_cli


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
