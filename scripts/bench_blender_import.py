# Times the Blender add-on's .hair import and export on a synthetic groom (docs/blender.md,
# "Speed"): N strands of M points with random positions, thickness and colours.
#   BLENDER_USER_SCRIPTS=$(mktemp -d) blender -b --factory-startup --python-exit-code 1 \
#       --python scripts/bench_blender_import.py -- build/blender/ringlet_blender.zip [N] [M] [REPEATS]
import os
import sys
import tempfile
import time

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip = args[0]
n = int(args[1]) if len(args) > 1 else 50000
m = int(args[2]) if len(args) > 2 else 32
repeats = int(args[3]) if len(args) > 3 else 3
bpy.ops.preferences.addon_install(filepath=addon_zip)
bpy.ops.preferences.addon_enable(module="ringlet_blender")
from ringlet_blender import hair_format, info_text  # noqa: E402

rng = np.random.default_rng(1)
points = rng.uniform(-0.3, 0.3, (n * m, 3)).astype(np.float32)
thickness = rng.uniform(4e-5, 1e-4, n * m).astype(np.float32)
colours = np.repeat(rng.uniform(0, 1, (n, 3)).astype(np.float32), m, axis=0)
folder = tempfile.mkdtemp()
path = os.path.join(folder, "bench.hair")
hair_format.write(path, hair_format.HairData(np.full(n, m), points, thickness, colours,
                                             info=info_text(1.0)))
size = os.path.getsize(path)
imports, exports = [], []
for _ in range(repeats):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)
    start = time.perf_counter()
    bpy.ops.ringlet.import_hair(filepath=path)
    imports.append(time.perf_counter() - start)
    start = time.perf_counter()
    bpy.ops.ringlet.export_hair(filepath=os.path.join(folder, "out.hair"))
    exports.append(time.perf_counter() - start)
print("bench: %d strands x %d points (%.1f MB): import min %.2f s (of %s), export min %.2f s (of %s)"
      % (n, m, size / 1e6, min(imports), ["%.2f" % t for t in imports], min(exports),
         ["%.2f" % t for t in exports]))
