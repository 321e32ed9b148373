"""The examples in examples/python: the Dask sweep on a two-worker LocalCluster, the student
notebook."""

import csv
import os
import subprocess
import sys

import pytest

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def test_eos_sweep_on_a_local_cluster_with_two_workers(tmp_path):
    pytest.importorskip("dask.distributed")
    pytest.importorskip("pandas")
    pytest.importorskip("matplotlib")
    out, runs, fig = tmp_path / "eos.csv", tmp_path / "runs.csv", tmp_path / "eos.png"
    subprocess.run(
        [sys.executable, str(EXAMPLES / "eos_sweep.py"), "--workers", "2",
         "--packings", "0.2,0.4", "--seeds", "2", "--n", "100", "--melt", "2",
         "--measure", "6", "--blocks", "3", "--out", str(out), "--runs-out", str(runs),
         "--plot", str(fig)],
        check=True, cwd=tmp_path, timeout=600,
    )
    rows = list(csv.DictReader(out.open()))
    assert [float(r["packing"]) for r in rows] == [0.2, 0.4]
    for r in rows:
        z, err, ref = float(r["Z"]), float(r["Z_error"]), float(r["Z_reference"])
        assert int(r["runs"]) == 2 and err > 0
        assert abs(z - ref) < 0.2 * ref, r
    assert len(list(csv.DictReader(runs.open()))) == 4
    assert fig.stat().st_size > 0


def test_student_example_runs(tmp_path):
    pytest.importorskip("matplotlib")
    env = dict(os.environ, MPLBACKEND="Agg")
    subprocess.run([sys.executable, str(EXAMPLES / "maxwell_speeds.py")], check=True,
                   cwd=tmp_path, env=env, timeout=600, capture_output=True)
    assert (tmp_path / "maxwell_speeds.png").stat().st_size > 0
