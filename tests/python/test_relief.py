# SPDX-License-Identifier: MIT
"""Conversion from Python: the same model as the command line (byte for byte), save and load,
reconstruction back to arrays, progress, Ctrl-C, and bad options."""
import os
import signal

import numpy as np
import pytest

import cellrelief as cr
from conftest import run_cli, uv_sphere


def test_the_model_is_the_command_lines_byte_for_byte(tmp_path, spot_path):
    status, output = run_cli("convert", spot_path, "-o", tmp_path / "cli.crm", "--grid", 6, "--texels", 9, "--no-error")
    assert status == 0, output
    model = cr.convert(cr.read_mesh(spot_path), grid=6, texels=9)
    model.save(tmp_path / "python.crm")
    assert (tmp_path / "python.crm").read_bytes() == (tmp_path / "cli.crm").read_bytes()


def test_save_load_and_reconstruct(tmp_path):
    v, f = uv_sphere()
    model, report = cr.convert(cr.Mesh(v, f), grid=4, texels=17, report=True)
    assert model.grid_size == 4 and model.texels == 17 and model.grey_cells == report["grey_cells"] > 0
    assert model.nbytes > 0 and model.distance_bits == 16
    path = tmp_path / "sphere.crm"
    model.save(path)
    loaded = cr.load_model(path)
    assert (loaded.grid_size, loaded.texels, loaded.grey_cells, loaded.nbytes) == (4, 17, model.grey_cells, model.nbytes)
    mesh = loaded.reconstruct()
    radii = np.linalg.norm(mesh.vertices, axis=1)
    assert mesh.face_count > 100
    assert abs(radii.mean() - 1) < 0.01 and np.abs(radii - 1).max() < 0.05
    coarse = loaded.reconstruct(lod=loaded.max_lod, method="per-face")
    assert 0 < coarse.face_count < mesh.face_count
    with pytest.raises(cr.InvalidArgumentError, match="method takes auto, closed or per-face"):
        loaded.reconstruct(method="marching")


def test_progress_is_called_in_order_up_to_one():
    v, f = uv_sphere()
    seen = []
    cr.convert(cr.Mesh(v, f), grid=8, texels=9, progress=seen.append)
    assert len(seen) >= 10
    assert all(a <= b for a, b in zip(seen, seen[1:]))
    assert seen[-1] == pytest.approx(1.0)


def test_ctrl_c_stops_a_conversion():
    v, f = uv_sphere()
    calls = []

    def interrupt(fraction):
        calls.append(fraction)
        if len(calls) == 3:
            os.kill(os.getpid(), signal.SIGINT)

    with pytest.raises(KeyboardInterrupt):
        cr.convert(cr.Mesh(v, f), grid=16, texels=33, progress=interrupt)
    assert calls[-1] < 1.0  # it stopped before the end


def test_bad_options_are_clear_errors():
    v, f = uv_sphere(rings=6, segments=8)
    mesh = cr.Mesh(v, f)
    with pytest.raises(cr.InvalidArgumentError, match="grid"):
        cr.convert(mesh, grid=0)
    with pytest.raises(cr.InvalidArgumentError, match="centre takes"):
        cr.convert(mesh, grid=2, centre="middle")
    with pytest.raises(cr.Error):
        cr.convert(mesh, grid=2, bits=12)
    with pytest.raises(cr.FileFormatError):
        cr.load_model(__file__)
