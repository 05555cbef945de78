# SPDX-License-Identifier: MIT
"""PolyCube-Maps from Python: polycube_map gives the command line's polycube and map on a real
mesh of genus 3, as arrays; the map saves to what `cellrelief render` reads and loads back; every
backend renders it as the CPU reference does; given cubes are taken back; bad arguments and a
polycube of the wrong genus are refused with the library's message."""
import numpy as np
import pytest

import cellrelief as cr
from conftest import available_backends, data_file, run_cli


@pytest.fixture(scope="module")
def three_holes_path():
    return data_file("meshes/small/3holes__cinolib.obj")


@pytest.fixture(scope="module")
def three_holes(three_holes_path):
    return cr.read_mesh(three_holes_path)


@pytest.fixture(scope="module")
def mapped(three_holes):
    sweeps = []
    result = cr.polycube_map(three_holes, progress=lambda sweep, d: sweeps.append((sweep, d["flipped"])))
    assert sweeps and sweeps[-1][1] == 0  # progress after each sweep, ending without folds
    return result


def test_the_map_is_the_command_lines(mapped, three_holes, three_holes_path, tmp_path):
    assert mapped.cubes_per_side == 10 and mapped.genus == 3
    assert mapped.texture.shape == (three_holes.vertex_count, 3) and mapped.texture.dtype == np.float32
    assert not mapped.texture.flags.writeable
    d = mapped.distortion
    assert d["optimized"]["flipped"] == 0 and d["sweeps"] > 0
    assert d["optimized"]["angle"] < d["start"]["angle"]
    assert mapped.t2.ndim == 3 and mapped.t2.shape[2] == 4 and mapped.use == "color"
    status, output = run_cli("polycube", three_holes_path, "-o", tmp_path / "cli")
    assert status == 0, output
    cli = cr.load_polycube(tmp_path / "cli")
    assert cli.distortion is None
    np.testing.assert_array_equal(cli.cubes, mapped.cubes)  # a polycube keeps its cubes sorted
    assert cli.cube_size == pytest.approx(mapped.cube_size, rel=1e-12)
    np.testing.assert_allclose(cli.origin, mapped.origin, rtol=0, atol=1e-9)
    np.testing.assert_allclose(cli.texture, mapped.texture, rtol=0, atol=1e-5)
    np.testing.assert_array_equal(cli.t2, mapped.t2)


def test_saved_maps_load_back_and_render_on_the_command_line(mapped, tmp_path):
    mapped.save(tmp_path / "saved")
    back = cr.load_polycube(tmp_path / "saved")
    np.testing.assert_array_equal(back.cubes, mapped.cubes)
    np.testing.assert_allclose(back.texture, mapped.texture, rtol=0, atol=1e-6)
    np.testing.assert_array_equal(back.t2, mapped.t2)
    png = tmp_path / "saved.png"
    status, output = run_cli("render", tmp_path / "saved", "--backend", "cpu", "--size", "64x64", "-o", png)
    assert status == 0 and "polycube map" in output, output
    assert png.exists()
    with pytest.raises(cr.FileNotFoundError, match="not a polycube result"):
        cr.load_polycube(tmp_path / "nothing")


def test_every_backend_renders_the_map_as_the_cpu_does(mapped):
    scene = cr.Scene()
    scene.add(mapped)
    assert "1 polycube maps" in repr(scene)
    camera = cr.Camera.framing(scene, yaw=30, pitch=25)
    names = available_backends()
    if names == ["cpu"]:
        pytest.skip("only the CPU backend runs here")
    frames = {name: cr.render(scene, camera, backend=name, width=96, height=96) for name in names}
    cpu = frames["cpu"]
    assert 0.1 < cpu.mask.mean() < 0.9
    for name, frame in frames.items():
        assert (frame.mask != cpu.mask).mean() < 2e-3, name
        both = frame.mask & cpu.mask
        assert np.median(np.abs(frame.color[both].astype(int) - cpu.color[both])) < 1, name


def test_given_cubes_are_taken_back(mapped, three_holes):
    again = cr.polycube_map(three_holes, cubes=mapped.cubes.astype(np.int64), origin=mapped.origin,
                            cube_size=mapped.cube_size, signal="normals", texels=8, sweeps=50)
    np.testing.assert_array_equal(again.cubes, mapped.cubes)
    assert again.cubes_per_side == 0 and again.use == "normal" and again.texels_per_squarelet == 8
    assert again.distortion["optimized"]["flipped"] == 0


def test_bad_arguments_are_refused(three_holes):
    with pytest.raises(cr.InvalidArgumentError, match="tutte"):
        cr.polycube_map(three_holes, energy="tutte")
    with pytest.raises(cr.InvalidArgumentError, match="not grid, normals"):
        cr.polycube_map(three_holes, signal="bumps")
    with pytest.raises(cr.InvalidInputError, match="no vertex colours"):
        cr.polycube_map(three_holes, signal="color")
    with pytest.raises(cr.InvalidArgumentError, match="power of two"):
        cr.polycube_map(three_holes, texels=12)
    with pytest.raises(cr.InvalidArgumentError, match="grid must lie"):
        cr.polycube_map(three_holes, grid=1)
    with pytest.raises(cr.InvalidArgumentError, match="an integer"):
        cr.polycube_map(three_holes, grid=1.5)
    with pytest.raises(cr.InvalidArgumentError, match="give one"):
        cr.polycube_map(three_holes, grid=8, cubes=[[0, 0, 0]])
    with pytest.raises(cr.InvalidArgumentError, match="beyond"):
        cr.polycube_map(three_holes, cubes=[[0, 0, 1 << 21]])
    with pytest.raises(cr.InvalidArgumentError, match=r"shape \(n, 3\)"):
        cr.polycube_map(three_holes, cubes=np.zeros((2, 2), dtype=np.int32))
    with pytest.raises(cr.InvalidArgumentError, match="give both or neither"):
        cr.polycube_map(three_holes, cubes=[[0, 0, 0]], origin=(0, 0, 0))
    with pytest.raises(cr.InvalidInputError, match="genus 0, the mesh 3"):
        cr.polycube_map(three_holes, cubes=[[0, 0, 0], [1, 0, 0]])
    with pytest.raises(cr.InvalidInputError, match="not a 2-manifold"):
        cr.polycube_map(three_holes, cubes=[[0, 0, 0], [1, 1, 0]])
