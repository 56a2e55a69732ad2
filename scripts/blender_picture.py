# Renders docs/images/blender_groom.png: a ringlet groom folder imported with the Blender add-on
# and rendered headless with Cycles and the Principled Hair BSDF. Run by make_blender_picture.sh:
#   blender -b --factory-startup --python scripts/blender_picture.py -- ADDON_ZIP GROOM_DIR OUT.png
#       [SIZE] [SAMPLES]
import os
import sys
import time

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
addon_zip, groom, image = args[:3]
size = int(args[3]) if len(args) > 3 else 480
samples = int(args[4]) if len(args) > 4 else 64

bpy.ops.preferences.addon_install(filepath=addon_zip)
bpy.ops.preferences.addon_enable(module="ringlet_blender")
for o in list(bpy.data.objects):
    bpy.data.objects.remove(o)
start = time.perf_counter()
bpy.ops.ringlet.import_output(directory=groom)
print("picture: folder import %.2f s" % (time.perf_counter() - start))
hair, body = bpy.data.objects["hair"], bpy.data.objects["body"]
print("picture: %d strands, %d points" % (len(hair.data.curves), len(hair.data.points)))

# Skin-like diffuse body, smooth shaded.
skin = bpy.data.materials.new("skin")
skin.use_nodes = True
skin.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.55, 0.42, 0.36, 1)
skin.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.6
body.data.materials.append(skin)
for polygon in body.data.polygons:
    polygon.use_smooth = True

scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.render.resolution_x = scene.render.resolution_y = size
scene.render.resolution_percentage = 100
scene.render.film_transparent = False
world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.6, 0.65, 0.7, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6
scene.world = world
sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 4.0
sun.data.angle = 0.1
sun.rotation_euler = (0.7, -0.5, 0.6)
scene.collection.objects.link(sun)

# Camera in front of the face (+y), to its left (-x) and a little above, looking at the head.
target = bpy.data.objects.new("target", None)
target.location = (0.0, 0.0, -0.1)
scene.collection.objects.link(target)
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
camera.location = (-0.55, 0.95, 0.12)
camera.data.lens = 50
constraint = camera.constraints.new("TRACK_TO")
constraint.target = target
constraint.track_axis = "TRACK_NEGATIVE_Z"
constraint.up_axis = "UP_Y"
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.filepath = image
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.compression = 100
start = time.perf_counter()
bpy.ops.render.render(write_still=True)
print("picture: Cycles %dx%d, %d samples: %.1f s -> %s"
      % (size, size, samples, time.perf_counter() - start, image))
