"""The sidebar panel (View3D > Sidebar > meshmorph), its settings (kept on
the scene) and the add-on's preferences."""

import bpy

from . import kept_correspondence


class MeshmorphSettings(bpy.types.PropertyGroup):
    marker_source: bpy.props.EnumProperty(
        name="Markers",
        items=(
            ("FILE", "Marker File", "meshmorph's marker file (as pick saves it), or two point files"),
            ("GROUPS", "Vertex Groups", "Vertex groups of the same name on both meshes"),
            ("EMPTIES", "Empties", "Empties parented to each mesh, paired by name (nose and nose.001)"),
        ),
        default="FILE",
    )
    marker_file: bpy.props.StringProperty(name="Marker File", subtype="FILE_PATH")
    target_points_file: bpy.props.StringProperty(
        name="Target Points", subtype="FILE_PATH", description="With point files (MeshLab .pp, Wrap .json): the target's"
    )
    group_prefix: bpy.props.StringProperty(name="Group Prefix", default="marker.")
    source_file: bpy.props.StringProperty(
        name="Source File",
        subtype="FILE_PATH",
        description="A glTF rig (.glb, .gltf, .vrm) whose morph targets are carried, read without importing it, "
        "instead of a selected source; the markers are a marker file between its mesh and the target",
    )
    source_mesh: bpy.props.StringProperty(
        name="Source Mesh",
        description="The Source File's mesh (its or its node's name); empty for the only one, else the one with the most vertices",
    )
    keys: bpy.props.StringProperty(name="Keys", description="The source's keys to carry, comma-separated; empty for all")
    refit: bpy.props.BoolProperty(name="New Fit", description="Fit a new correspondence even when the target keeps one")
    inbetween_from: bpy.props.StringProperty(name="From", description="The key to start from; empty for the basis")
    inbetween_to: bpy.props.StringProperty(name="To")
    inbetween_count: bpy.props.IntProperty(name="In-betweens", default=3, min=1, soft_max=20)
    bake_keys: bpy.props.StringProperty(name="Through", description="The keys to animate through, comma-separated (the basis by its name)")
    frames_per_key: bpy.props.IntProperty(name="Frames per Key", default=12, min=1, soft_max=240)
    landmark_source: bpy.props.EnumProperty(
        name="Landmarks",
        items=(
            ("FILE", "Landmark File", "A point file (MeshLab .pp, Wrap .json, lines of name x y z or name VERTEX)"),
            ("GROUPS", "Vertex Groups", "Vertex groups named the Group Prefix and a landmark (marker.chin, marker.31)"),
            ("EMPTIES", "Empties", "Empties parented to the head, named by their landmark (chin, noseTip, 31)"),
        ),
        default="EMPTIES",
        description="Where the head's landmarks are: each named by its iBUG 300-W number (1 to 68) or an alias",
    )
    landmark_file: bpy.props.StringProperty(name="Landmark File", subtype="FILE_PATH")
    replace_keys: bpy.props.BoolProperty(
        name="Replace Keys", description="Write over the head's shape keys that have an ARKit name"
    )


class MeshmorphPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    executable: bpy.props.StringProperty(
        name="meshmorph command",
        subtype="FILE_PATH",
        description="The meshmorph executable for picking markers; empty to find it on PATH",
    )

    def draw(self, context):
        self.layout.prop(self, "executable")


class MESHMORPH_PT_panel(bpy.types.Panel):
    bl_label = "meshmorph"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "meshmorph"

    def draw(self, context):
        s = context.scene.meshmorph
        obj = context.active_object
        keys = obj.data.shape_keys if obj is not None and obj.type == "MESH" else None
        layout = self.layout

        box = layout.box()
        box.label(text="Transfer shape keys (source, then target active)")
        box.prop(s, "source_file")
        if s.source_file:
            box.prop(s, "source_mesh")
        box.prop(s, "marker_source")
        if s.marker_source == "FILE":
            box.prop(s, "marker_file")
            box.prop(s, "target_points_file")
        elif s.marker_source == "GROUPS":
            box.prop(s, "group_prefix")
        box.operator("meshmorph.pick", icon="URL")
        box.prop(s, "keys")
        box.prop(s, "refit")
        box.operator("meshmorph.transfer_shape_keys", icon="SHAPEKEY_DATA")
        kept = kept_correspondence.describe(obj) if obj is not None else None
        if kept:
            for line in kept.split(". "):
                box.label(text=line)
            box.operator("meshmorph.forget_correspondence")

        box = layout.box()
        box.label(text="As-rigid-as-possible in-betweens")
        if keys is not None:
            box.prop_search(s, "inbetween_from", keys, "key_blocks")
            box.prop_search(s, "inbetween_to", keys, "key_blocks")
        box.prop(s, "inbetween_count")
        box.operator("meshmorph.add_inbetweens")
        box.prop(s, "bake_keys")
        box.prop(s, "frames_per_key")
        box.operator("meshmorph.bake_animation")

        box = layout.box()
        box.label(text="ARKit expressions (the head active)")
        box.prop(s, "landmark_source")
        if s.landmark_source == "FILE":
            box.prop(s, "landmark_file")
        elif s.landmark_source == "GROUPS":
            box.prop(s, "group_prefix")
        box.prop(s, "replace_keys")
        box.operator("meshmorph.arkit_expressions", icon="SHAPEKEY_DATA")


CLASSES = (MeshmorphSettings, MeshmorphPreferences, MESHMORPH_PT_panel)
