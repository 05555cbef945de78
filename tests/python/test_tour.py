# SPDX-License-Identifier: MIT
"""The tour of docs/python.md runs as written and writes its two pictures."""
import os
import pathlib
import subprocess
import sys

from conftest import data_file


def test_the_tour_runs(tmp_path):
    script = pathlib.Path(__file__).resolve().parents[2] / "apps" / "python" / "examples" / "tour.py"
    data = data_file("meshes/small/spot__common-3d-test-models.obj").parents[2]
    done = subprocess.run([sys.executable, str(script), str(data), str(tmp_path)], capture_output=True, text=True,
                          timeout=600, env=dict(os.environ))
    assert done.returncode == 0, done.stdout + done.stderr
    assert "indirection map (" in done.stdout
    for name in ("tour_backends.png", "tour_indirection.png"):
        assert (tmp_path / name).stat().st_size > 10000
