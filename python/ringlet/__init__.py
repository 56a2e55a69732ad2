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
Models, scenes, bodies, hairstyles, results, grooms and hair curves pickle bit for bit and support
copy.copy / copy.deepcopy (multiprocessing, joblib). Type stubs: ringlet/__init__.pyi.
"""

from . import _ringlet
from ._ringlet import *  # noqa: F401,F403  (the extension holds the whole API)
from ._ringlet import Error  # noqa: F401  (explicit: the exception every call may raise)

__version__ = "0.1.0"

# The public names, so that help(ringlet) lists the classes and functions (pydoc shows a
# module's classes only when they are its own or listed in __all__), and the classes report
# themselves as ringlet.X (repr, pickles: ringlet.StrandModel is where pickle finds them).
__all__ = sorted(name for name in dir(_ringlet) if not name.startswith("_"))
for _name in __all__:
    _value = getattr(_ringlet, _name)
    if isinstance(_value, type) and _value.__module__ == "ringlet._ringlet":
        _value.__module__ = "ringlet"
del _name, _value
