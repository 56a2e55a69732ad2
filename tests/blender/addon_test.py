# The Blender add-on (blender/ringlet_blender) under headless Blender, as a user would get it:
# the zipped add-on is installed and enabled in a temporary user scripts folder (the caller sets
# BLENDER_USER_SCRIPTS / BLENDER_USER_CONFIG to it), a groom written by `ringlet groom` is
# imported and compared with the files read independently here (struct/numpy, not the add-on's
# reader), exported and re-imported bit for bit, and rendered with Cycles and the Principled Hair
# BSDF.
#
#   blender -b --factory-startup --python-exit-code 1 --python addon_test.py -- \
#       ADDON_ZIP RINGLET HAIRSTYLE WORKDIR [IMAGE_OUT]
#
# Exits non-zero (through --python-exit-code) on the first failed check, with a message.
import os
import struct
import subprocess
import sys
import time

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
ADDON_ZIP, RINGLET, HAIRSTYLE, WORK = args[:4]
IMAGE_OUT = args[4] if len(args) > 4 else None
CHECKS = [0]


def check(condition, message):
    if not condition:
        raise AssertionError(message)
    CHECKS[0] += 1


# --- Install and enable the zipped add-on (into BLENDER_USER_SCRIPTS, a temporary folder). ---
scripts = os.environ.get("BLENDER_USER_SCRIPTS", "")
check(scripts.startswith(WORK), "BLENDER_USER_SCRIPTS must point into the test's folder, got %r"
      % scripts)
bpy.ops.preferences.addon_install(filepath=ADDON_ZIP)
bpy.ops.preferences.addon_enable(module="ringlet_blender")
import ringlet_blender  # noqa: E402  (installed just above)
check(os.path.realpath(ringlet_blender.__file__).startswith(os.path.realpath(scripts)),
      "the add-on was not loaded from the temporary scripts folder: %s" % ringlet_blender.__file__)
check(hasattr(bpy.ops.ringlet, "import_hair") and hasattr(bpy.ops.ringlet, "export_hair") and
      hasattr(bpy.ops.ringlet, "import_output"), "the add-on's operators are not registered")
menu_ids = []
for menu in (bpy.types.TOPBAR_MT_file_import, bpy.types.TOPBAR_MT_file_export):
    menu_ids += [f.__name__ for f in menu._dyn_ui_initialize()]
check("menu_import" in menu_ids and "menu_export" in menu_ids,
      "the File > Import/Export menu entries are missing: %s" % menu_ids)

# --- A small groom written by ringlet. ---
out = os.path.join(WORK, "groom")
result = subprocess.run([RINGLET, "groom", HAIRSTYLE, "-o", out, "--quiet"],
                        capture_output=True, text=True)
check(result.returncode == 0, "ringlet groom failed (%d): %s" % (result.returncode,
                                                               result.stderr))


def read_hair(path):
    """The .hair file by the specification's byte offsets (independent of the add-on)."""
    data = open(path, "rb").read()
    check(data[:4] == b"HAIR", "%s: no HAIR signature" % path)
    strands, points, arrays, default_segments = struct.unpack_from("<4I", data, 4)
    offset = 128
    if arrays & 1:
        counts = np.frombuffer(data, "<u2", strands, offset).astype(np.int64) + 1
        offset += 2 * strands
    else:
        counts = np.full(strands, default_segments + 1, dtype=np.int64)
    check(arrays & 2, "no points array")
    pts = np.frombuffer(data, "<f4", 3 * points, offset).reshape(points, 3)
    offset += 12 * points
    thickness = None
    if arrays & 4:
        thickness = np.frombuffer(data, "<f4", points, offset)
        offset += 4 * points
    if arrays & 8:
        offset += 4 * points
    colours = None
    if arrays & 16:
        colours = np.frombuffer(data, "<f4", 3 * points, offset).reshape(points, 3)
        offset += 12 * points
    check(offset == len(data), "%s: %d bytes, the arrays end at %d" % (path, len(data), offset))
    return counts, pts, thickness, colours, data


counts, points, thickness, colours, hair_bytes = read_hair(os.path.join(out, "strands.hair"))
check(counts.size > 10 and thickness is not None and colours is not None,
      "the groom's .hair lacks strands, thickness or colours")


def curves_arrays(obj):
    c = obj.data
    n = len(c.points)
    got_counts = np.empty(len(c.curves), dtype=np.int32)
    c.curves.foreach_get("points_length", got_counts)
    got_points = np.empty(3 * n, dtype=np.float32)
    c.points.foreach_get("position", got_points)
    got_radii = np.empty(n, dtype=np.float32)
    c.attributes["radius"].data.foreach_get("value", got_radii)
    return got_counts, got_points.reshape(n, 3), got_radii


def same_bits(a, b):
    a = np.ascontiguousarray(a, dtype=np.float32)
    b = np.ascontiguousarray(b, dtype=np.float32)
    return a.shape == b.shape and np.array_equal(a.view(np.uint32), b.view(np.uint32))


# --- File > Import > ringlet output folder: the hair as a Curves object, the body mesh. ---
for o in list(bpy.data.objects):  # the factory scene's cube, camera and light
    bpy.data.objects.remove(o)
start = time.perf_counter()
check(bpy.ops.ringlet.import_output(directory=out) == {"FINISHED"}, "import_output failed")
folder_seconds = time.perf_counter() - start
hair = bpy.data.objects.get("hair")
body = bpy.data.objects.get("body")
check(hair is not None and hair.type == "CURVES",
      "no hair Curves object after the folder import: %s" % [(o.name, o.type)
                                                             for o in bpy.data.objects])
check(isinstance(hair.data, bpy.types.Curves), "the hair is not a Curves datablock")
check(body is not None and body.type == "MESH", "no body mesh after the folder import")
got_counts, got_points, got_radii = curves_arrays(hair)
check(np.array_equal(got_counts, counts), "curve point counts differ from the file")
check(same_bits(got_points, points), "positions differ from the file (bit for bit)")
# radius = thickness / 2 (the .hair thickness is the diameter; halving a float is exact).
check(same_bits(got_radii, thickness / np.float32(2.0)), "radii are not thickness / 2")
check(np.array_equal(np.asarray(hair.matrix_world), np.eye(4)),
      "the hair object has a transform (expected world = file coordinates)")
check(hair.parent == body and hair.data.surface == body, "the hair is not attached to the body")
rgba = np.empty(4 * points.shape[0], dtype=np.float32)
hair.data.attributes["color"].data.foreach_get("color", rgba)
check(same_bits(rgba.reshape(-1, 4)[:, :3], colours), "the colour attribute differs from the file")
# The body: the mannequin's 9 spheres joined into one mesh, 9 x (23 x 48 + 2) vertices
# (docs/file-formats.md, body.obj), every vertex on one of the spheres (mannequin.json).
check(len(body.data.vertices) == 9 * (23 * 48 + 2),
      "body has %d vertices, expected 9 UV spheres" % len(body.data.vertices))
spheres = [((0.0, 0.0, 0.0), 0.1), ((0.0, 0.04, -0.08), 0.055), ((0.0, -0.01, -0.14), 0.055),
           ((0.0, -0.01, -0.35), 0.13), ((0.13, -0.01, -0.28), 0.065),
           ((-0.13, -0.01, -0.28), 0.065), ((0.19, -0.01, -0.38), 0.055),
           ((-0.19, -0.01, -0.38), 0.055), ((0.0, -0.01, -0.52), 0.13)]
co = np.empty(3 * len(body.data.vertices), dtype=np.float32)
body.data.vertices.foreach_get("co", co)
co = co.reshape(-1, 3).astype(np.float64) @ np.asarray(body.matrix_world)[:3, :3].T
off_surface = np.min([np.abs(np.linalg.norm(co - c, axis=1) - r) for c, r in spheres], axis=0)
check(off_surface.max() < 1e-6, "body vertices are %.3g m off the mannequin's spheres (z up?)"
      % off_surface.max())
material = hair.data.materials[0]
check(any(n.bl_idname == "ShaderNodeBsdfHairPrincipled" for n in material.node_tree.nodes),
      "the hair material has no Principled Hair BSDF")
# The body gets a skin-like material (issue 25, item 9: it rendered washed-out white).
check(len(body.data.materials) == 1 and body.data.materials[0].name.startswith("ringlet skin"),
      "the body has no skin material: %s" % [m.name for m in body.data.materials if m])
skin = next(n for n in body.data.materials[0].node_tree.nodes
            if n.bl_idname == "ShaderNodeBsdfPrincipled")
check(np.allclose(skin.inputs["Base Color"].default_value[:3], (0.80, 0.54, 0.42)),
      "the skin's base colour is %s" % (tuple(skin.inputs["Base Color"].default_value),))

# --- Blender's own OBJ importer keeps every 2-vertex segment of strands.obj (issue 14: it kept
# only the first edge of each polyline), z up with Forward Y, Up Z. ---
before = set(bpy.data.objects)
bpy.ops.wm.obj_import(filepath=os.path.join(out, "strands.obj"), forward_axis="Y", up_axis="Z")
obj_hair = [o for o in bpy.data.objects if o not in before]
check(len(obj_hair) == 1 and obj_hair[0].type == "MESH", "strands.obj: expected one mesh")
check(len(obj_hair[0].data.edges) == points.shape[0] - counts.size,
      "strands.obj: Blender's importer kept %d edges, the hair has %d segments"
      % (len(obj_hair[0].data.edges), points.shape[0] - counts.size))
obj_co = np.empty(3 * len(obj_hair[0].data.vertices), dtype=np.float32)
obj_hair[0].data.vertices.foreach_get("co", obj_co)
obj_co = obj_co.reshape(-1, 3) @ np.asarray(obj_hair[0].matrix_world, dtype=np.float32)[:3, :3].T
check(obj_co.shape == points.shape and np.abs(obj_co - points).max() < 1e-6,
      "strands.obj: vertices differ from the .hair points (axes?)")
bpy.data.objects.remove(obj_hair[0])

# --- Export > Hair (.hair) and back: bit-exact. ---
exported = os.path.join(WORK, "exported.hair")
bpy.ops.object.select_all(action="DESELECT")
hair.select_set(True)
bpy.context.view_layer.objects.active = hair
check(bpy.ops.ringlet.export_hair(filepath=exported) == {"FINISHED"}, "export failed")
e_counts, e_points, e_thickness, e_colours, e_bytes = read_hair(exported)
check(np.array_equal(e_counts, counts), "exported point counts differ")
check(same_bits(e_points, points), "exported positions differ from the groom's (bit for bit)")
check(same_bits(e_thickness, thickness), "exported thickness differs from the groom's")
check(same_bits(e_colours, colours), "exported colours differ from the groom's")
# The header: counts, array bits and the unit text as ringlet writes them; only the default
# thickness/colour (means, summed in another order) may differ in the last bit.
check(e_bytes[:20] == hair_bytes[:20], "exported header counts/arrays differ")
check(e_bytes[40:128] == hair_bytes[40:128], "exported info text differs: %r"
      % e_bytes[40:128].rstrip(b"\0"))
check(e_bytes[128:] == hair_bytes[128:], "exported arrays differ from the groom's bytes")
# Import the export: the same curves again.
check(bpy.ops.ringlet.import_hair(filepath=exported) == {"FINISHED"}, "import_hair failed")
again = bpy.context.view_layer.objects.active
check(again is not None and again.type == "CURVES" and again != hair, "no new Curves object")
a_counts, a_points, a_radii = curves_arrays(again)
check(np.array_equal(a_counts, counts) and same_bits(a_points, points) and
      same_bits(a_radii, got_radii), "export -> import did not give the same curves")
# A moved object exports in world coordinates (translation by (0, 0, 1): z + 1 in float64).
again.location = (0.0, 0.0, 1.0)
bpy.context.view_layer.update()
moved = os.path.join(WORK, "moved.hair")
check(bpy.ops.ringlet.export_hair(filepath=moved) == {"FINISHED"}, "export of the moved hair")
m_counts, m_points, _, _, _ = read_hair(moved)
shifted = points.copy()
shifted[:, 2] = (points[:, 2].astype(np.float64) + 1.0).astype(np.float32)
check(same_bits(m_points, shifted), "the moved hair was not exported in world coordinates")
bpy.data.objects.remove(again)

# Curves of varying point counts (a hand-made groom): written with a segments array, read back.
variable = os.path.join(WORK, "variable.hair")
rng = np.random.default_rng(3)
v_counts = rng.integers(2, 9, size=40)
v_points = rng.uniform(-0.2, 0.2, size=(int(v_counts.sum()), 3)).astype(np.float32)
v_radii = rng.uniform(2e-5, 6e-5, size=int(v_counts.sum())).astype(np.float32)
from ringlet_blender import curves_data  # noqa: E402
made = curves_data.create_curves_object(bpy.context, "variable", v_counts, v_points, v_radii)
bpy.context.view_layer.objects.active = made
check(bpy.ops.ringlet.export_hair(filepath=variable) == {"FINISHED"}, "export of varying counts")
r_counts, r_points, r_thickness, r_colours, r_bytes = read_hair(variable)
check(struct.unpack_from("<I", r_bytes, 12)[0] & 1, "no segments array for varying counts")
check(np.array_equal(r_counts, v_counts) and same_bits(r_points, v_points) and
      same_bits(r_thickness, v_radii * np.float32(2.0)) and r_colours is None,
      "varying counts did not round-trip")
bpy.data.objects.remove(made)
# A groom made in Blender has no radius attribute: Export writes ringlet's default radius
# (50 um: thickness 1e-4 m at every point) and says so, never thickness 0 (issue 25, item 9).
made = curves_data.create_curves_object(bpy.context, "no_radius", v_counts, v_points, v_radii)
made.data.attributes.remove(made.data.attributes["radius"])
check(made.data.attributes.get("radius") is None, "the radius attribute was not removed")
bpy.context.view_layer.objects.active = made
no_radius = os.path.join(WORK, "no_radius.hair")
check(bpy.ops.ringlet.export_hair(filepath=no_radius) == {"FINISHED"}, "export without radius")
n_counts, n_points, n_thickness, _, _ = read_hair(no_radius)
check(n_thickness is not None and same_bits(n_thickness, np.full(n_points.shape[0],
                                                                  np.float32(50e-6) * 2)),
      "a Curves without radius was not written with the default thickness 1e-4 m")
# Files get the user's umask (0666 & ~umask), not mkstemp's private 0600.
old_mask = os.umask(0o027)
try:
    check(bpy.ops.ringlet.export_hair(filepath=no_radius) == {"FINISHED"}, "export (umask 027)")
finally:
    os.umask(old_mask)
check(os.stat(no_radius).st_mode & 0o777 == 0o640, "exported mode %o with umask 027, expected 640"
      % (os.stat(no_radius).st_mode & 0o777))
check(os.stat(exported).st_mode & 0o777 == 0o666 & ~old_mask, "exported mode %o with umask %o"
      % (os.stat(exported).st_mode & 0o777, old_mask))
# The wrong object active and no hair selected: a message saying what to select.
bpy.ops.object.select_all(action="DESELECT")
bpy.context.view_layer.objects.active = body
try:
    outcome = bpy.ops.ringlet.export_hair(filepath=os.path.join(WORK, "never.hair"))
except RuntimeError as e:
    outcome = str(e)
check("select the hair Curves object" in str(outcome) and "\"body\" is a mesh" in str(outcome),
      "export with the body active: %r" % (outcome,))
check(not os.path.exists(os.path.join(WORK, "never.hair")), "a refused export wrote a file")
bpy.data.objects.remove(made)
# ringlet's own reader (DecodeHairFile, through `ringlet render`) accepts the exports.
for path in (exported, variable, no_radius):
    result = subprocess.run([RINGLET, "render", path, "-o", path + ".png", "--width", "8",
                             "--height", "8", "--spp", "1", "--quiet"],
                            capture_output=True, text=True)
    check(result.returncode == 0, "ringlet does not read the add-on's %s: %s"
          % (os.path.basename(path), result.stderr))

# Bad files: an error report, no object, no exception.
bad = os.path.join(WORK, "bad.hair")
open(bad, "wb").write(hair_bytes[:200])
objects_before = len(bpy.data.objects)
try:
    outcome = bpy.ops.ringlet.import_hair(filepath=bad)
except RuntimeError as e:  # operators that report ERROR raise in background mode
    outcome = str(e)
check(outcome != {"FINISHED"} and "truncated" in str(outcome),
      "a truncated file was not refused with a message: %r" % (outcome,))
check(len(bpy.data.objects) == objects_before, "a refused import left an object behind")

# --- A tiny Cycles render with the Principled Hair BSDF: the hair shows. ---
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 4
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = 32
scene.render.resolution_percentage = 100
world = bpy.data.worlds.new("white")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
scene.world = world
body.hide_render = True  # the hair alone against a white background
# A 32-pixel image of a 30-cm groom has 1-cm pixels, where a 0.1-mm fibre covers 1% of a pixel:
# thicken the fibres 150 times for this render only, so that the test sees them.
radius = hair.data.attributes["radius"]
radius.data.foreach_set("value", got_radii * np.float32(150.0))
hair.data.update_tag()
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
scene.camera = camera
# Orthographic camera looking along +y at the hair's box, which fills the frame.
lo, hi = points.min(axis=0), points.max(axis=0)
camera.data.type = "ORTHO"
camera.data.ortho_scale = float(max(hi[0] - lo[0], hi[2] - lo[2])) * 1.6
camera.location = (float(lo[0] + hi[0]) / 2, float(lo[1]) - 1.0, float(lo[2] + hi[2]) / 2)
camera.rotation_euler = (np.pi / 2, 0.0, 0.0)
image_path = os.path.join(WORK, "render.png")
scene.render.filepath = image_path
scene.render.image_settings.file_format = "PNG"
start = time.perf_counter()
bpy.ops.render.render(write_still=True)
render_seconds = time.perf_counter() - start
image = bpy.data.images.load(image_path)
pixels = np.array(image.pixels[:], dtype=np.float32).reshape(32, 32, image.channels)[:, :, :3]
# Project the hair's points to pixels (the orthographic camera: x -> column, z -> row) and
# compare the hair's pixels with the background's.
scale = camera.data.ortho_scale
u = (points[:, 0] - camera.location[0]) / scale + 0.5
v = (points[:, 2] - camera.location[2]) / scale + 0.5
hit = np.zeros((32, 32), dtype=bool)
hit[np.clip((v * 32).astype(int), 0, 31), np.clip((u * 32).astype(int), 0, 31)] = True
brightness = pixels.mean(axis=2)
check(hit.sum() > 20 and (~hit).sum() > 20, "the hair covers %d pixels" % hit.sum())
check(brightness[~hit].max() > 0.5,
      "the background is not bright (max %.3f): the render is black" % brightness[~hit].max())
check(brightness[hit].mean() < brightness[~hit].mean() - 0.1,
      "the hair's pixels (mean %.3f) are not darker than the background's (%.3f): no hair"
      % (brightness[hit].mean(), brightness[~hit].mean()))
check(np.isfinite(pixels).all(), "non-finite pixels")
if IMAGE_OUT:
    import shutil
    shutil.copy(image_path, IMAGE_OUT)

print("addon_test: %d checks passed; %d strands, %d points; folder import %.2f s; "
      "Cycles 32x32 render %.2f s" % (CHECKS[0], counts.size, points.shape[0], folder_seconds,
                                       render_seconds))
