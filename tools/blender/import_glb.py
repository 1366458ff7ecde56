"""Blender script: import a GLB, print its shape keys and animation range.

Run through import_glb.sh, or as
    blender --background --factory-startup --python import_glb.py -- FILE.glb
with MESHMORPH_BLENDER_NUMPY naming a folder that holds numpy < 1.24.
Exits with status 1 when the file has no shape keys.
"""
import os
import sys

numpy_dir = os.environ.get("MESHMORPH_BLENDER_NUMPY")
if numpy_dir:
    sys.path.insert(0, numpy_dir)

import bpy  # noqa: E402

glb = sys.argv[sys.argv.index("--") + 1]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb)

print("meshmorph-import:", os.path.basename(glb))
found = 0
for obj in bpy.context.scene.objects:
    if obj.type != "MESH":
        continue
    mesh = obj.data
    keys = mesh.shape_keys.key_blocks if mesh.shape_keys else []
    # The first key block is the basis, not a morph target.
    shapes = [k.name for k in keys][1:]
    found += len(shapes)
    print(f"object {obj.name!r}: {len(mesh.vertices)} vertices, {len(mesh.polygons)} faces")
    print(f"shape keys ({len(shapes)}): {', '.join(shapes)}")
    print("shape key values:", ", ".join(f"{k.value:g}" for k in keys[1:]))
    for slot, material in enumerate(mesh.materials):
        used = sum(1 for p in mesh.polygons if p.material_index == slot)
        images = []
        if material and material.use_nodes:
            images = [n.image.name for n in material.node_tree.nodes if n.type == "TEX_IMAGE" and n.image]
        name = material.name if material else None
        print(f"material {name!r}: {used} faces, textures: {', '.join(images) or 'none'}")
    action = mesh.shape_keys.animation_data.action if mesh.shape_keys and mesh.shape_keys.animation_data else None
    if action:
        start, end = action.frame_range
        print(f"animation {action.name!r}: frames {start:g} to {end:g}, {len(action.fcurves)} curves")
    else:
        print("animation: none")
scene = bpy.context.scene
print(f"scene frames {scene.frame_start} to {scene.frame_end} at {scene.render.fps / scene.render.fps_base:g} fps")
sys.exit(0 if found else 1)
