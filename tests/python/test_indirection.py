# SPDX-License-Identifier: MIT
"""Indirection maps from Python: from an array or a file, with any optimizer of the table, lower
distortion than the identity with no flipped cell, and bad heights or names refused."""
import numpy as np
import pytest

import cellrelief as cr
from conftest import data_file


def bumps(size=64):
    u = (np.arange(size) + 0.5) / size
    return (0.5 + 0.25 * np.sin(6 * np.pi * u)[None, :] * np.cos(4 * np.pi * u)[:, None]).astype(np.float32)


def test_the_table_lists_gauss_newton_first():
    names = [name for name, _ in cr.optimizers()]
    assert names[0] == "gauss-newton" and "springs" in names


@pytest.mark.parametrize("optimizer", ["gauss-newton", "springs"])
def test_an_array_gets_a_map_that_lowers_distortion(optimizer):
    I, report = cr.indirection_map(bumps(), optimizer=optimizer, grid=16, height_scale=0.2, report=True)
    assert I.shape == (64, 64, 2) and I.dtype == np.float32 and np.isfinite(I).all()
    assert np.abs(I).max() > 1e-3
    assert report["flipped_cells"] == 0
    assert report["l2_stretch"] < report["l2_stretch_before"]


def test_a_file_gives_what_the_array_of_its_heights_gives():
    lion = data_file("heightmaps/sponza/lion_bump.png")
    I = cr.indirection_map(lion, grid=16, size=32)
    assert I.shape == (32, 32, 2) and np.isfinite(I).all()


def test_bad_heights_and_names_are_refused():
    with pytest.raises(cr.InvalidArgumentError, match=r"outside \[0, 1\]"):
        cr.indirection_map(bumps() * 3, grid=8)
    with pytest.raises(cr.InvalidArgumentError, match="2D array"):
        cr.indirection_map(np.zeros((4, 4, 2)), grid=8)
    with pytest.raises(cr.Error, match="gauss-newton"):  # the message lists the valid names
        cr.indirection_map(bumps(), optimizer="newton", grid=8)
    with pytest.raises(cr.InvalidArgumentError, match="height_scale"):
        cr.indirection_map(bumps(), grid=8, height_scale=-1)
