"""Gonio from Python: read, check, convert and compare photometric files
(IES LM-63, EULUMDAT, IES TM-33, GLDF, TM-25 ray files' far field) and
simulate luminaire models, on the libraries the `gonio` command uses.

    >>> import gonio
    >>> lamp = gonio.read("lamp.ies")
    >>> lamp.summary()["flux_lm"]
    >>> lamp.candela.shape            # (C-planes, gamma angles), no copy
    >>> result = gonio.simulate("bell.gltf", photons=100_000, iterations=4)
    >>> result.photometry.summary()["beam_angle_c0_c180_deg"]

help(gonio.read), help(gonio.Photometry), help(gonio.simulate) explain each
call; docs/python.md has the whole surface in one table.
"""
from gonio._gonio import *  # noqa: F401,F403  (every public name of the compiled module)
from gonio._gonio import __version__  # noqa: F401
