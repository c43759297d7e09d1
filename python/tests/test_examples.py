"""The examples in examples/ run as a reader would run them, so they cannot rot: each ends
without an error, prints what docs/python.md shows and writes its plot."""

import subprocess
import sys

from conftest import REPO


def test_first_steps(tmp_path):
    out = tmp_path / "plot.png"
    p = subprocess.run([sys.executable, str(REPO / "examples" / "first_steps.py"), "-o", str(out)],
                       capture_output=True, text=True, timeout=120, cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0] == "<Robot 'MK2 Plus': 4 DH rows, 3 joint variables, 3 motors>"
    assert "tool at [254.295 146.817 144.636] mm" in lines
    assert "ik: reached by closed, q = [ -36.87    78.096 -102.227] deg, 0.0000 mm from the target" in lines
    assert "ik of a point out of reach: unreachable, 259.9 mm short" in lines
    assert "demo.arm: 10 commands, 0 rejected, worst quantization error 1.132 mm, 3.309 s" in lines
    assert out.stat().st_size > 20000 and out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
