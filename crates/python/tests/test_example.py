"""The notebook-style example runs as a script and draws its figure."""

import os
import subprocess
import sys

from conftest import REPO


def test_the_example_script_runs_and_plots(tmp_path):
    figure = tmp_path / "contact_curve.png"
    script = REPO / "examples" / "python" / "contact_curve.py"
    done = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", str(script), str(figure)],
                          capture_output=True, text=True, cwd=tmp_path,
                          env={**os.environ, "MPLBACKEND": "Agg"})
    assert done.returncode == 0, done.stderr
    assert figure.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and figure.stat().st_size > 20_000
    assert "figure:" in done.stdout
