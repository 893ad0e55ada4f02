"""examples/sweep_resolution.py runs (small resolutions) and writes its PNG."""
import os
import subprocess
import sys

import camplace
from conftest import ROOT


def test_sweep_resolution_writes_its_plot(tmp_path, tiny_files):
    # The hand-built scene: its exact evaluation takes milliseconds, paper_basic's seconds.
    scene, cameras = tiny_files
    out = tmp_path / "sweep.png"
    result = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "sweep_resolution.py"), "--scene", scene,
         "--cameras", cameras, "--resolutions", "4x3x2,8x6x4", "--modes", "center,conservative",
         "--out", str(out)],
        capture_output=True, text=True, cwd=tmp_path, check=False,
        env=dict(os.environ, MPLBACKEND="Agg",
                 PYTHONPATH=os.path.dirname(os.path.abspath(camplace.__file__))))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.stat().st_size > 10000
    lines = result.stdout.splitlines()
    assert lines[0].split()[:2] == ["mode", "resolution"]
    assert [line.split()[:2] for line in lines[1:5]] == [
        ["center", "4x3x2"], ["center", "8x6x4"], ["conservative", "4x3x2"],
        ["conservative", "8x6x4"]]
    assert lines[-1] == f"wrote {out}"
