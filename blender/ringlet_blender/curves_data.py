# Blender hair Curves objects <-> flat strand arrays (numpy), with bulk foreach_get/foreach_set
# only: no Python loop over points or strands.
#
# Blender 3.4's Python API can create an empty hair Curves datablock (bpy.data.hair_curves.new)
# but cannot size it: Curves.add_curves does not exist there (checked with Blender 3.4.1). So a
# Curves datablock of the right topology is made the way 3.4 allows: a temporary mesh holding one
# chain of edges per strand (vertices in file order) goes through a geometry-nodes "Mesh to Curve"
# modifier, and bpy.ops.object.convert(target='CURVES') realizes the evaluated curves into a new
# Curves datablock. Mesh to Curve starts a curve at each chain end in vertex order, so the curves
# come out in strand order, root to tip; the code checks the resulting offsets against the wanted
# point counts and then writes the exact positions and radii itself (bit for bit, float32).
import bpy
import numpy as np

TEMPORARY = "ringlet_import_tmp"


def _new_node_group():
    """A geometry-nodes group Input -> Mesh to Curve -> Output (Blender 3.4 socket API, or the
    4.x interface API where ng.inputs no longer exists)."""
    group = bpy.data.node_groups.new(TEMPORARY, "GeometryNodeTree")
    if hasattr(group, "interface"):  # Blender 4.0+
        group.interface.new_socket("Geometry", in_out="INPUT", socket_type="NodeSocketGeometry")
        group.interface.new_socket("Geometry", in_out="OUTPUT", socket_type="NodeSocketGeometry")
    else:
        group.inputs.new("NodeSocketGeometry", "Geometry")
        group.outputs.new("NodeSocketGeometry", "Geometry")
    group_in = group.nodes.new("NodeGroupInput")
    group_out = group.nodes.new("NodeGroupOutput")
    to_curve = group.nodes.new("GeometryNodeMeshToCurve")
    group.links.new(group_in.outputs[0], to_curve.inputs["Mesh"])
    group.links.new(to_curve.outputs[0], group_out.inputs[0])
    return group


def _chain_mesh(point_counts, points):
    """A mesh with the points as vertices and edges (i, i + 1) inside each strand."""
    mesh = bpy.data.meshes.new(TEMPORARY)
    n = points.shape[0]
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", points.reshape(-1))
    ends = np.cumsum(point_counts.astype(np.int64))
    not_last = np.ones(n, dtype=bool)
    not_last[ends - 1] = False
    first = np.nonzero(not_last)[0]
    edges = np.empty((first.size, 2), dtype=np.int32)
    edges[:, 0] = first
    edges[:, 1] = first + 1
    mesh.edges.add(first.size)
    mesh.edges.foreach_set("vertices", edges.reshape(-1))
    mesh.update()
    return mesh


def create_curves_object(context, name, point_counts, points, radii, colors=None):
    """A new hair Curves object linked to the active collection.

    point_counts: int array (strands,), each >= 2; points: float32 (points, 3) in metres,
    object space; radii: float32 (points,) fibre radius in metres; colors: optional float32
    (points, 3) linear RGB stored as the point attribute "color". Raises RuntimeError if
    Blender did not produce the expected curves."""
    point_counts = np.asarray(point_counts, dtype=np.int64)
    points = np.ascontiguousarray(points, dtype=np.float32).reshape(-1, 3)
    radii = np.ascontiguousarray(radii, dtype=np.float32).reshape(-1)
    mesh = _chain_mesh(point_counts, points)
    temporary = bpy.data.objects.new(name, mesh)
    context.collection.objects.link(temporary)
    group = _new_node_group()
    modifier = temporary.modifiers.new(TEMPORARY, "NODES")
    modifier.node_group = group
    # object.convert acts on the selected objects: select only the temporary one (the previous
    # selection is dropped; the new hair ends up selected and active, as after any import).
    for o in context.view_layer.objects:
        if o.select_get():
            o.select_set(False)
    temporary.select_set(True)
    context.view_layer.objects.active = temporary
    try:
        result = bpy.ops.object.convert(target="CURVES")
    finally:
        bpy.data.node_groups.remove(group)
    obj = context.view_layer.objects.active
    if "FINISHED" not in result or obj is None or obj.type != "CURVES":
        if temporary.name in bpy.data.objects:
            bpy.data.objects.remove(temporary)
        if mesh.users == 0:
            bpy.data.meshes.remove(mesh)
        raise RuntimeError("Blender did not convert the strands to a Curves object")
    # The temporary mesh is no longer used by any object (object.convert leaves it orphaned, but
    # with a stale user count of 1 in Blender 3.4.1: removing it then printed a red
    # "ERROR (bke.lib_id_delete) ... still has 1 users" on every import). When no ID uses it
    # (bpy.data.user_map), clear the count first.
    if not bpy.data.user_map(subset=[mesh])[mesh]:
        mesh.user_clear()
        bpy.data.meshes.remove(mesh)
    curves = obj.data
    curves.name = name
    strands = point_counts.size
    if len(curves.curves) != strands or len(curves.points) != points.shape[0]:
        raise RuntimeError("Blender made %d curves of %d points, expected %d of %d"
                           % (len(curves.curves), len(curves.points), strands, points.shape[0]))
    first = np.empty(strands, dtype=np.int32)
    curves.curves.foreach_get("first_point_index", first)
    expected = (np.cumsum(point_counts) - point_counts).astype(np.int32)
    if not np.array_equal(first, expected):
        raise RuntimeError("Blender reordered the strands while building the curves")
    # Mesh to Curve leaves helper attributes: keep only what describes the hair.
    # (".select_vert"/".select_edge" are the mesh's selection, meaningless on curves).
    for attribute_name in [a.name for a in curves.attributes]:
        if attribute_name not in ("position", "curve_type"):
            attribute = curves.attributes.get(attribute_name)
            if attribute is not None:
                curves.attributes.remove(attribute)
    set_point_attributes(curves, points, radii, colors)
    return obj


def set_point_attributes(curves, points, radii, colors=None):
    """Writes positions, the "radius" attribute and, if given, the "color" attribute."""
    curves.points.foreach_set("position", points.reshape(-1))
    radius = curves.attributes.get("radius")
    if radius is None:
        radius = curves.attributes.new("radius", "FLOAT", "POINT")
    radius.data.foreach_set("value", radii)
    if colors is not None:
        color = curves.attributes.get("color")
        if color is None:
            color = curves.attributes.new("color", "FLOAT_COLOR", "POINT")
        rgba = np.ones((points.shape[0], 4), dtype=np.float32)
        rgba[:, :3] = colors
        color.data.foreach_set("color", rgba.reshape(-1))
    curves.update_tag()


def read_curves(curves):
    """The strands of a Curves datablock: (point_counts int64, points float32 (n, 3) object
    space, radii float32 (n,) or None, colors float32 (n, 3) or None)."""
    strands = len(curves.curves)
    n = len(curves.points)
    counts = np.empty(strands, dtype=np.int32)
    curves.curves.foreach_get("points_length", counts)
    points = np.empty(3 * n, dtype=np.float32)
    curves.points.foreach_get("position", points)
    radii = None
    radius = curves.attributes.get("radius")
    if radius is not None and radius.domain == "POINT" and radius.data_type == "FLOAT":
        radii = np.empty(n, dtype=np.float32)
        radius.data.foreach_get("value", radii)
    colors = None
    color = curves.attributes.get("color")
    if color is not None and color.domain == "POINT" and color.data_type in ("FLOAT_COLOR",
                                                                             "BYTE_COLOR"):
        rgba = np.empty(4 * n, dtype=np.float32)
        color.data.foreach_get("color", rgba)
        colors = rgba.reshape(n, 4)[:, :3].copy()
    return counts.astype(np.int64), points.reshape(n, 3), radii, colors
