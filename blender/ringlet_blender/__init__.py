# ringlet's Blender add-on: imports ringlet's hair (.hair) as a hair Curves object, imports a
# `ringlet groom` output folder (hair and body), and exports a Curves object as .hair so that a
# Blender groom can be a target for ringlet. It reads and writes files only; the physics stays in
# ringlet (docs/blender.md).
bl_info = {
    "name": "ringlet hair (.hair, groom folders)",
    "author": "ringlet",
    "version": (1, 0, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > Hair (.hair) / ringlet output folder; File > Export > Hair (.hair)",
    "description": "Import and export Cem Yuksel's .hair files as hair Curves objects, and "
                   "import ringlet groom folders (strands.hair + body.obj)",
    "category": "Import-Export",
}

import os
import time

import bpy
import numpy as np
from bpy.props import BoolProperty, FloatProperty, StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import curves_data, hair_format

UNIT_NAMES = {1.0: " (metres)", 100.0: " (centimetres)", 1000.0: " (millimetres)"}

# The fibre radius exported for a Curves object without a "radius" attribute (a groom made with
# Blender's own tools has none): ringlet's default, the paper's 50-um mean radius of human hair
# (kDefaultRadius in include/ringlet/scene_json.h), i.e. a thickness (diameter) of 0.1 mm.
DEFAULT_RADIUS = 50e-6

# The body's default skin: a Principled BSDF with subsurface scattering, a light skin tone
# (linear RGB) and a matte roughness; Cycles and Eevee render it as skin, not a white blank.
SKIN_COLOUR = (0.80, 0.54, 0.42)


def info_text(units_per_metre):
    """The info text ringlet writes (ringlet::DefaultHairInfo in src/io/hair_file.cpp): the
    shortest decimal of the unit, "unit" for 1, the unit's name for 1, 100 and 1000."""
    value = float(units_per_metre)
    number = repr(value)
    if number.endswith(".0"):
        number = number[:-2]
    return "ringlet hair curves; %s %s per metre%s; z up; thickness: diameter" % (
        number, "unit" if value == 1.0 else "units", UNIT_NAMES.get(value, ""))


def hair_material(color):
    """A material with Cycles' Principled Hair BSDF whose absorption reproduces the file's
    colour: ringlet writes the display colour c = exp(-3 sigma_a) (hair_bsdf.h,
    MelaninDisplayColour), so sigma_a = -ln(c) / 3 per channel, the absorption coefficient the
    BSDF's "Absorption coefficient" parametrization takes (both follow Chiang et al. 2016)."""
    material = bpy.data.materials.new("ringlet hair")
    material.use_nodes = True
    nodes = material.node_tree.nodes
    for node in list(nodes):
        nodes.remove(node)
    output = nodes.new("ShaderNodeOutputMaterial")
    bsdf = nodes.new("ShaderNodeBsdfHairPrincipled")
    bsdf.parametrization = "ABSORPTION"
    c = np.clip(np.asarray(color, dtype=np.float64), 1e-6, 1.0)
    sigma = -np.log(c) / 3.0
    socket = bsdf.inputs["Absorption Coefficient"]
    socket.default_value = tuple(sigma[:3]) + ((1.0,) if len(socket.default_value) == 4 else ())
    material.node_tree.links.new(bsdf.outputs[0], output.inputs["Surface"])
    material.diffuse_color = (float(c[0]), float(c[1]), float(c[2]), 1.0)  # viewport colour
    return material


def skin_material():
    """A skin-like default material for imported bodies (ringlet's body.obj has none): Principled
    BSDF, base colour SKIN_COLOUR, subsurface 0.1 with a reddish radius, roughness 0.5."""
    material = bpy.data.materials.new("ringlet skin")
    material.use_nodes = True
    bsdf = next((n for n in material.node_tree.nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"),
                None)
    if bsdf is not None:
        bsdf.inputs["Base Color"].default_value = SKIN_COLOUR + (1.0,)
        bsdf.inputs["Roughness"].default_value = 0.5
        for name, value in (("Subsurface", 0.1), ("Subsurface Weight", 0.1)):
            if name in bsdf.inputs:  # Blender 3.x calls it Subsurface, 4.x Subsurface Weight
                bsdf.inputs[name].default_value = value
        if "Subsurface Radius" in bsdf.inputs:
            bsdf.inputs["Subsurface Radius"].default_value = (1.0, 0.2, 0.1)
        if "Subsurface Color" in bsdf.inputs:  # Blender 3.x
            bsdf.inputs["Subsurface Color"].default_value = SKIN_COLOUR + (1.0,)
    material.diffuse_color = SKIN_COLOUR + (1.0,)  # viewport colour
    return material


def import_hair(context, path, units_per_metre=0.0, surface=None, with_material=True,
                name=None):
    """Reads a .hair file and creates a hair Curves object; returns (object, seconds, info).

    units_per_metre 0 takes the unit ringlet states in the file's info text, metres otherwise.
    Positions become metres (file value / units_per_metre, in float64 then rounded to float32 as
    ringlet's reader does; exact for metres), the radius is half the file's thickness (the
    thickness is the fibre diameter). With a surface object, the hair is parented to it (keeping
    its world position) and the Curves' surface is set to it."""
    start = time.perf_counter()
    hair = hair_format.read(path)
    if units_per_metre <= 0.0:
        units_per_metre = hair_format.units_per_metre_from_info(hair.info) or 1.0
    if units_per_metre == 1.0:
        points = hair.points
        radii = hair.widths() * np.float32(0.5)
    else:
        points = (hair.points.astype(np.float64) / units_per_metre).astype(np.float32)
        radii = (hair.widths().astype(np.float64) / units_per_metre).astype(np.float32) * \
            np.float32(0.5)
    name = name or os.path.splitext(os.path.basename(path))[0]
    obj = curves_data.create_curves_object(context, name, hair.point_counts, points, radii,
                                           hair.colors)
    if with_material:
        color = hair.colors.mean(axis=0) if hair.colors is not None and hair.num_points else \
            hair.default_color
        obj.data.materials.append(hair_material(color))
    if surface is not None:
        attach(obj, surface)
    return obj, time.perf_counter() - start, hair


def attach(obj, surface):
    """Parents the hair to the surface (world position kept) and sets it as the Curves'
    surface (used by Blender's curves sculpt tools; the surface UV map is set when the surface
    mesh has one)."""
    obj.parent = surface
    obj.matrix_parent_inverse = surface.matrix_world.inverted()
    if surface.type == "MESH":
        obj.data.surface = surface
        if surface.data.uv_layers.active is not None:
            obj.data.surface_uv_map = surface.data.uv_layers.active.name


def export_hair(obj, path, units_per_metre=1.0, apply_transform=True,
                default_radius=DEFAULT_RADIUS):
    """Writes a Curves object as .hair: points (world space when apply_transform, in file
    units), thickness = 2 x radius (metres x units_per_metre), the "color" attribute if any.
    A Curves without a "radius" attribute (a groom made in Blender) is written with
    default_radius (m, ringlet's 50 um unless given) at every point, scaled with the object like
    a radius attribute would be. Returns (the HairData written, whether the default radius was
    used)."""
    counts, points, radii, colors = curves_data.read_curves(obj.data)
    defaulted = radii is None
    if defaulted:
        if not (np.isfinite(default_radius) and default_radius > 0.0):
            raise ValueError("default radius: expected a finite number > 0 (m), got %r"
                             % (default_radius,))
        radii = np.full(points.shape[0], default_radius, dtype=np.float32)
    matrix = np.array(obj.matrix_world, dtype=np.float64)
    if apply_transform and not np.array_equal(matrix, np.eye(4)):
        p = points.astype(np.float64) @ matrix[:3, :3].T + matrix[:3, 3]
        points = p.astype(np.float32)
        if radii is not None:
            # a uniform scale scales the radius; for other transforms the mean axis scale.
            scale = float(np.cbrt(abs(np.linalg.det(matrix[:3, :3]))))
            radii = (radii.astype(np.float64) * scale).astype(np.float32)
    if units_per_metre != 1.0:
        points = (points.astype(np.float64) * units_per_metre).astype(np.float32)
    thickness = None
    if radii is not None:
        thickness = radii * np.float32(2.0)
        if units_per_metre != 1.0:
            thickness = (radii.astype(np.float64) * 2.0 * units_per_metre).astype(np.float32)
    hair = hair_format.HairData(counts, points, thickness, colors, info=info_text(units_per_metre))
    hair_format.write(path, hair)
    return hair, defaulted


class RINGLET_OT_import_hair(bpy.types.Operator, ImportHelper):
    """Import a .hair file (Cem Yuksel's format, as written by ringlet) as a hair Curves object"""
    bl_idname = "ringlet.import_hair"
    bl_label = "Import Hair (.hair)"
    bl_options = {"REGISTER", "UNDO", "PRESET"}

    filename_ext = ".hair"
    filter_glob: StringProperty(default="*.hair", options={"HIDDEN"})
    units_per_metre: FloatProperty(
        name="File units per metre", default=0.0, min=0.0, soft_max=1000.0,
        description="Length unit of the file per metre (1 metres, 100 centimetres); 0 reads the "
                    "unit ringlet writes in the header, metres for other files")
    surface: StringProperty(
        name="Surface", default="",
        description="Optional mesh object the hair grows on: the hair is parented to it and "
                    "it becomes the Curves surface")
    material: BoolProperty(name="Hair material", default=True,
                           description="Add a Principled Hair BSDF material of the file's colour")

    def draw(self, context):
        layout = self.layout
        layout.prop(self, "units_per_metre")
        layout.prop_search(self, "surface", context.scene, "objects")
        layout.prop(self, "material")

    def execute(self, context):
        surface = None
        if self.surface:
            surface = bpy.data.objects.get(self.surface)
            if surface is None:
                self.report({"ERROR"}, "surface: no object named \"%s\"" % self.surface)
                return {"CANCELLED"}
        try:
            obj, seconds, hair = import_hair(context, self.filepath, self.units_per_metre,
                                             surface, self.material)
        except (OSError, hair_format.HairFileError, RuntimeError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "%s: %d strands, %d points in %.2f s"
                    % (obj.name, hair.num_strands, hair.num_points, seconds))
        return {"FINISHED"}


def import_output_folder(context, directory, with_body=True, with_material=True):
    """Imports a `ringlet groom`/`ringlet style` output folder: body.obj (if present) as a mesh,
    then strands.hair as hair Curves parented to it. Returns (hair object, body object or
    None)."""
    hair_path = os.path.join(directory, "strands.hair")
    if not os.path.isfile(hair_path):
        raise OSError("%s: no strands.hair in this folder (is it a ringlet output folder?)"
                      % directory)
    body = None
    body_path = os.path.join(directory, "body.obj")
    if with_body and os.path.isfile(body_path):
        before = set(bpy.data.objects)
        # ringlet's OBJ files are z up, metres: no axis conversion (Blender's C++ OBJ importer,
        # in Blender since 3.2).
        bpy.ops.wm.obj_import(filepath=body_path, forward_axis="Y", up_axis="Z")
        new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
        if new and with_material:
            skin = skin_material()
            for o in new:
                o.data.materials.clear()
                o.data.materials.append(skin)
        if new:
            body = new[0]
            if len(new) > 1:  # one object per body component: join them into one surface
                for o in context.view_layer.objects:
                    o.select_set(False)
                for o in new:
                    o.select_set(True)
                context.view_layer.objects.active = body
                bpy.ops.object.join()
            body.name = "body"
    hair, seconds, data = import_hair(context, hair_path, 0.0, body, with_material,
                                      name="hair")
    return hair, body, seconds, data


class RINGLET_OT_import_output(bpy.types.Operator):
    """Import a ringlet output folder (strands.hair and body.obj written by `ringlet groom`)"""
    bl_idname = "ringlet.import_output"
    bl_label = "Import ringlet output folder"
    bl_options = {"REGISTER", "UNDO"}

    directory: StringProperty(name="Folder", subtype="DIR_PATH")
    filter_folder: BoolProperty(default=True, options={"HIDDEN"})
    body: BoolProperty(name="Body", default=True, description="Also import body.obj")
    material: BoolProperty(name="Hair material", default=True,
                           description="Add a Principled Hair BSDF material of the hair colour")

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def execute(self, context):
        try:
            hair, body, seconds, data = import_output_folder(context, self.directory, self.body,
                                                             self.material)
        except (OSError, hair_format.HairFileError, RuntimeError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        self.report({"INFO"}, "%d strands%s in %.2f s" % (
            data.num_strands, " and the body" if body else "", seconds))
        return {"FINISHED"}


class RINGLET_OT_export_hair(bpy.types.Operator, ExportHelper):
    """Export the active hair Curves object as a .hair file (a target for ringlet)"""
    bl_idname = "ringlet.export_hair"
    bl_label = "Export Hair (.hair)"

    filename_ext = ".hair"
    filter_glob: StringProperty(default="*.hair", options={"HIDDEN"})
    units_per_metre: FloatProperty(name="File units per metre", default=1.0, min=1e-6,
                                   description="1 writes metres (ringlet's default)")
    apply_transform: BoolProperty(name="World space", default=True,
                                  description="Apply the object's transform to the points")
    default_radius: FloatProperty(
        name="Default radius", default=DEFAULT_RADIUS, min=1e-9, soft_max=1e-3, precision=6,
        unit="LENGTH",
        description="Fibre radius written for curves without a radius attribute (grooms made "
                    "in Blender have none): ringlet's default 50 um")

    def execute(self, context):
        # The object to export: the active one if it is hair, else the one selected hair Curves
        # object; anything else gets a message saying what to select (not Blender's bare
        # "context is incorrect" of a failed poll).
        obj = context.active_object
        if obj is None or obj.type != "CURVES":
            selected = [o for o in context.selected_objects if o.type == "CURVES"]
            if len(selected) != 1:
                what = "nothing is active" if obj is None else \
                    "the active object \"%s\" is a %s" % (obj.name, obj.type.lower())
                self.report({"ERROR"}, "Export Hair (.hair): select the hair Curves object to "
                            "export and make it active (%s; %d hair Curves objects selected)"
                            % (what, len(selected)))
                return {"CANCELLED"}
            obj = selected[0]
        try:
            hair, defaulted = export_hair(obj, self.filepath, self.units_per_metre,
                                          self.apply_transform, self.default_radius)
        except (OSError, ValueError, hair_format.HairFileError) as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        if defaulted:
            self.report({"WARNING"}, "%s has no radius attribute: wrote the default radius "
                        "%.3g m (thickness %.3g m) at every point"
                        % (obj.name, self.default_radius, 2.0 * self.default_radius))
        self.report({"INFO"}, "%s: %d strands, %d points" % (self.filepath, hair.num_strands,
                                                           hair.num_points))
        return {"FINISHED"}


def menu_import(self, context):
    self.layout.operator(RINGLET_OT_import_hair.bl_idname, text="Hair (.hair)")
    self.layout.operator(RINGLET_OT_import_output.bl_idname, text="ringlet output folder")


def menu_export(self, context):
    self.layout.operator(RINGLET_OT_export_hair.bl_idname, text="Hair (.hair)")


CLASSES = (RINGLET_OT_import_hair, RINGLET_OT_import_output, RINGLET_OT_export_hair)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.TOPBAR_MT_file_import.append(menu_import)
    bpy.types.TOPBAR_MT_file_export.append(menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(menu_import)
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
