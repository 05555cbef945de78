# SPDX-License-Identifier: MIT
"""Scenes, backends and rays from Python: every backend renders the same pixels as the CPU
reference, frames come back as arrays, batches of rays meet an analytic sphere where they should,
and bad rays or names are refused."""
import numpy as np
import pytest

import cellrelief as cr
from conftest import available_backends, data_file, uv_sphere


@pytest.fixture(scope="module")
def sphere_scene():
    v, f = uv_sphere()
    scene = cr.Scene()
    scene.add(cr.convert(cr.Mesh(v, f), grid=4, texels=17))
    return scene


def test_every_backend_renders_what_the_cpu_renders(sphere_scene):
    camera = cr.Camera.framing(sphere_scene, yaw=30, pitch=20)
    names = available_backends()
    assert "cpu" in names
    frames = {name: cr.render(sphere_scene, camera, backend=name, width=96, height=64) for name in names}
    cpu = frames["cpu"]
    assert cpu.color.shape == (64, 96, 4) and cpu.color.dtype == np.uint8
    assert cpu.depth.shape == (64, 96) and cpu.normal.shape == (64, 96, 3) and cpu.mask.dtype == bool
    assert 0.05 < cpu.mask.mean() < 0.9  # the framing fits the grid's cube, larger than the sphere
    assert np.isinf(cpu.depth[~cpu.mask]).all() and np.isfinite(cpu.depth[cpu.mask]).all()
    np.testing.assert_allclose(np.linalg.norm(cpu.normal[cpu.mask], axis=1), 1, atol=1e-4)
    for name, frame in frames.items():
        assert (frame.mask != cpu.mask).mean() < 1e-3, name
        both = frame.mask & cpu.mask
        assert np.median(np.abs(frame.depth[both] - cpu.depth[both])) < 1e-4, name
        assert np.abs(frame.color[both].astype(int) - cpu.color[both]).mean() < 1.0, name


def test_a_renderer_keeps_its_backend_and_takes_channels(sphere_scene):
    renderer = cr.Renderer("cpu")
    assert renderer.name == "cpu" and "CPU" in renderer.description
    with pytest.raises(cr.InvalidArgumentError, match="upload a scene"):
        renderer.render(cr.Camera((0, 0, 5), (0, 0, 0)))
    renderer.upload(sphere_scene)
    frame = renderer.render(cr.Camera((0, 0, 5), (0, 0, 0)), width=32, height=32, channels=["depth"])
    assert frame.color is None and frame.depth.shape == (32, 32)
    assert frame.depth[16, 16] == pytest.approx(4.0, abs=0.02)
    with pytest.raises(cr.InvalidArgumentError, match="channels take"):
        renderer.render(cr.Camera((0, 0, 5), (0, 0, 0)), channels=["colour"])
    with pytest.raises(cr.InvalidArgumentError):
        cr.Renderer("metal")


def test_rays_from_numpy_meet_the_sphere(sphere_scene):
    rng = np.random.default_rng(7)
    n = 20000
    directions = rng.normal(size=(n, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    origins = -4.0 * directions + rng.uniform(-0.3, 0.3, size=(n, 3))
    hits = cr.trace(sphere_scene, origins, directions)
    assert hits["t"].shape == (n,) and hits["normal"].shape == (n, 3) and hits["cell"].dtype == np.int32
    # The analytic answer: |o + t d| = 1.
    b = np.einsum("ij,ij->i", origins, directions)
    c = np.einsum("ij,ij->i", origins, origins) - 1
    disc = b * b - c
    expected_hit = disc > 1e-4
    grazing = np.abs(disc) <= 1e-4
    assert (hits["hit"][~grazing] == expected_hit[~grazing]).mean() > 0.999
    both = hits["hit"] & expected_hit
    exact = -b[both] - np.sqrt(disc[both])
    # The mesh's faces lie inside the unit sphere, up to 1 - cos(pi / 48) = 0.002 deep.
    assert np.median(np.abs(hits["t"][both] - exact)) < 5e-3
    assert (hits["t"][both] > exact - 1e-3).mean() > 0.99
    points = origins[both] + hits["t"][both, None] * directions[both]
    cosine = np.einsum("ij,ij->i", hits["normal"][both], points / np.linalg.norm(points, axis=1, keepdims=True))
    assert np.median(cosine) > 0.999
    assert (hits["cell"][both] >= 0).all() and np.isinf(hits["t"][~hits["hit"]]).all()


def test_bad_rays_are_refused(sphere_scene):
    tracer = cr.Tracer(sphere_scene)
    with pytest.raises(cr.InvalidArgumentError, match="as many rows"):
        tracer.trace(np.zeros((3, 3)), np.ones((2, 3)))
    with pytest.raises(cr.InvalidArgumentError, match="row 1 is zero"):
        tracer.trace(np.zeros((2, 3)), [[0, 0, 1], [0, 0, 0]])
    with pytest.raises(cr.InvalidArgumentError, match="not finite"):
        tracer.trace([[0, 0, np.inf]], [[0, 0, 1]])
    with pytest.raises(cr.InvalidArgumentError, match=r"shape \(n, 3\)"):
        tracer.trace(np.zeros((2, 2)), np.zeros((2, 2)))


def test_a_relief_surface_renders_on_every_backend():
    rocks = data_file("heightmaps/pom_dxsdk/rocks_NM_height.tga")
    scene = cr.Scene()
    scene.add(cr.relief_surface(rocks, height_scale=0.05, wrap="repeat"))
    camera = cr.Camera.framing(scene, yaw=20, pitch=40)
    cpu = cr.render(scene, camera, backend="cpu", width=80, height=60)
    assert cpu.mask.mean() > 0.2
    for name in available_backends():
        frame = cr.render(scene, camera, backend=name, width=80, height=60)
        assert (frame.mask != cpu.mask).sum() <= 2, name
    with pytest.raises(cr.InvalidArgumentError, match="square tile"):
        cr.relief_surface(rocks, v_axis=(0, 2, 0))


def test_threads_sharing_a_renderer_get_the_frames_one_thread_gets(sphere_scene):
    # render releases the GIL: without the renderer's lock two threads wrote into one frame buffer.
    import threading

    renderer = cr.Renderer("cpu")
    renderer.upload(sphere_scene)
    cameras = [cr.Camera.framing(sphere_scene, yaw=yaw, pitch=20) for yaw in (0, 40, 80, 120)]
    alone = [renderer.render(c, width=64, height=48).depth.copy() for c in cameras]
    results = {}

    def work(i):
        results[i] = renderer.render(cameras[i % 4], width=64, height=48).depth.copy()
        renderer.upload(sphere_scene)  # uploads interleaved with other threads' renders

    threads = [threading.Thread(target=work, args=(i,)) for i in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(results) == 8
    for i, depth in results.items():
        np.testing.assert_array_equal(depth, alone[i % 4])
