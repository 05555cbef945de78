# SPDX-License-Identifier: MIT
"""cellrelief: relief representations of surfaces and their ray tracing, from Python.

Meshes, frames and maps are NumPy arrays: ``Mesh(vertices, faces)`` takes (n, 3) and (m, 3) arrays,
``convert`` turns a mesh into a relief model, ``Renderer("vulkan").render(...)`` gives a frame whose
``color``, ``depth``, ``normal`` and ``mask`` are arrays, ``trace`` takes (n, 3) origins and
directions. Errors are ``cellrelief.Error`` subclasses that carry the library's message. See
docs/python.md.
"""

from ._cellrelief import *  # noqa: F401,F403
from ._cellrelief import __version__  # noqa: F401
