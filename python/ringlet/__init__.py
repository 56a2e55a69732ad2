"""ringlet: hair shapes from the statics of Kirchhoff rods (Bertails et al., Eurographics 2005).

Bindings of the C++ library (numpy in and out, SI units: metres, kilograms, seconds); the names
are the C++ API's, functions in snake_case (``SolveStrands`` -> ``solve``, ``ReadHairFile`` ->
``read_hair_file``). Documentation: docs/python.md in the source tree.

    import ringlet
    results = ringlet.solve("examples/vertical_curly.json", points_per_segment=8)
    results[0].points              # (N, 3) float64 view, metres
    groom = ringlet.groom("examples/hairstyles/wavy.json")
    groom.strands.points           # (K, 3) float32 view, metres

Errors raise ringlet.Error (a ValueError and RuntimeError) with the library's one-line message.
Long solves, grooms, styling operations and renders release the GIL and stop on Ctrl-C.
"""

from ._ringlet import *  # noqa: F401,F403  (the extension holds the whole API)
from ._ringlet import Error  # noqa: F401  (explicit: the exception every call may raise)

__version__ = "0.1.0"
