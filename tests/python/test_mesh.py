# SPDX-License-Identifier: MIT
"""Meshes from NumPy arrays and files: round trips of every accepted dtype, read-only views of the
mesh's own memory, and bad arrays refused with an error that names the argument."""
import numpy as np
import pytest

import cellrelief as cr
from conftest import uv_sphere


@pytest.mark.parametrize("vdtype", [np.float32, np.float64])
@pytest.mark.parametrize("fdtype", [np.int32, np.int64, np.uint32])
def test_arrays_round_trip_in_every_dtype(vdtype, fdtype):
    v, f = uv_sphere(rings=6, segments=8)
    mesh = cr.Mesh(v.astype(vdtype), f.astype(fdtype))
    assert mesh.vertex_count == len(v) and mesh.face_count == len(f)
    assert mesh.vertices.dtype == np.float32 and mesh.vertices.shape == v.shape
    assert mesh.faces.dtype == np.uint32 and mesh.faces.shape == f.shape
    np.testing.assert_array_equal(mesh.vertices, v.astype(np.float32))
    np.testing.assert_array_equal(mesh.faces, f)
    np.testing.assert_allclose(mesh.bounds(), [[-1, -1, -1], [1, 1, 1]], atol=1e-6)


def test_views_share_the_mesh_memory_and_are_read_only():
    v, f = uv_sphere(rings=4, segments=6)
    mesh = cr.Mesh(v, f)
    a, b = mesh.vertices, mesh.vertices
    assert np.shares_memory(a, b)  # a view, not a copy per access
    with pytest.raises(ValueError):
        a[0, 0] = 5
    del mesh  # the view keeps the mesh alive
    assert a.shape == v.shape and np.isfinite(a).all()


def test_uvs_per_vertex_become_per_corner():
    v, f = uv_sphere(rings=4, segments=6)
    uv = np.stack([v[:, 0], v[:, 1]], axis=1) * 0.5 + 0.5
    mesh = cr.Mesh(v, f, uvs=uv)
    assert mesh.uvs.shape == (3 * len(f), 2)
    np.testing.assert_allclose(mesh.uvs[:3], uv[f[0]], rtol=1e-6)
    assert cr.Mesh(v, f).uvs is None


@pytest.mark.parametrize(
    "vertices, faces, words",
    [
        (np.zeros((4, 2)), [[0, 1, 2]], "vertices must have shape (n, 3)"),
        ([["a", "b", "c"]] * 3, [[0, 1, 2]], "vertices must hold real numbers"),
        ([[0, 0, 0], [1, 0, np.nan], [0, 1, 0]], [[0, 1, 2]], "not finite"),
        (np.eye(3), [[0, 1, 3]], "refers to vertex 3"),
        (np.eye(3), [[0, -1, 2]], "refers to vertex -1"),
        (np.eye(3), [[0.0, 1.0, 2.0]], "faces must hold integers"),
        (np.eye(3), [[0, 1]], "faces must have shape (n, 3)"),
    ],
)
def test_bad_arrays_are_refused_with_a_clear_error(vertices, faces, words):
    with pytest.raises(cr.InvalidArgumentError) as caught:
        cr.Mesh(vertices, faces)
    assert words in str(caught.value)
    assert isinstance(caught.value, ValueError) and isinstance(caught.value, cr.Error)


def test_files_round_trip_and_errors_name_the_file(tmp_path, spot_path):
    spot = cr.read_mesh(spot_path)
    assert spot.face_count == 5856 and spot.uvs is not None
    out = tmp_path / "spot.ply"
    cr.write_mesh(spot, out)
    again = cr.read_mesh(out)
    assert again.face_count == spot.face_count
    np.testing.assert_allclose(again.bounds(), spot.bounds(), rtol=1e-6)
    with pytest.raises(cr.FileNotFoundError) as caught:
        cr.read_mesh(tmp_path / "absent.obj")
    assert "absent.obj" in str(caught.value)
    assert isinstance(caught.value, FileNotFoundError)  # the built-in one catches it too
    bad = tmp_path / "bad.obj"
    bad.write_text("v 0 0 0\nf 1 2 3\n")
    with pytest.raises(cr.Error) as caught:
        cr.read_mesh(bad)
    assert "bad.obj" in str(caught.value)
