# SPDX-License-Identifier: MIT
"""Shared fixtures of the Python tests: the data folder (../shared/data), real files that fail the
test under CI when missing (and skip it elsewhere), and the command line for comparisons."""
import os
import pathlib
import subprocess

import numpy as np
import pytest

import cellrelief as cr

IN_CI = os.environ.get("CI") == "true"


def data_file(relative):
    path = pathlib.Path(os.environ.get("CELLRELIEF_DATA_DIR", "../shared/data")) / relative
    if not path.exists():
        if IN_CI:
            pytest.fail(f"test data missing under CI: {path}")
        pytest.skip(f"test data not found: {path}")
    return path


@pytest.fixture
def spot_path():
    return data_file("meshes/small/spot__common-3d-test-models.obj")


def run_cli(*args):
    """The `cellrelief` program of this build, its output and status."""
    cli = os.environ["CELLRELIEF_CLI"]
    done = subprocess.run([cli, *map(str, args)], capture_output=True, text=True, timeout=300)
    return done.returncode, done.stdout + done.stderr


def uv_sphere(radius=1.0, rings=24, segments=48):
    """A closed latitude-longitude sphere (poles welded), counter-clockwise from outside."""
    vertices = [(0.0, 0.0, radius)]
    for j in range(1, rings):
        theta = np.pi * j / rings
        for i in range(segments):
            phi = 2 * np.pi * i / segments
            vertices.append((radius * np.sin(theta) * np.cos(phi), radius * np.sin(theta) * np.sin(phi),
                             radius * np.cos(theta)))
    vertices.append((0.0, 0.0, -radius))
    south = len(vertices) - 1

    def ring(j, i):
        return 1 + (j - 1) * segments + i % segments

    faces = []
    for i in range(segments):
        faces.append((0, ring(1, i), ring(1, i + 1)))
        faces.append((south, ring(rings - 1, i + 1), ring(rings - 1, i)))
    for j in range(1, rings - 1):
        for i in range(segments):
            a, b, c, d = ring(j, i), ring(j + 1, i), ring(j + 1, i + 1), ring(j, i + 1)
            faces += [(a, b, c), (a, c, d)]
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def available_backends():
    """The backends that run here; under CI every one must."""
    names = []
    for b in cr.backends():
        if b["available"]:
            names.append(b["name"])
        elif IN_CI:
            pytest.fail(f"backend {b['name']} is unavailable under CI: {b['reason']}")
    return names
