"""The README's picture of the add-on: a horse pose carried to the camel as
a shape key inside Blender, rendered by Blender in the background.

    tools/blender-package
    blender -b --factory-startup --python blender/docs_picture.py -- target/blender/meshmorph-*-legacy.zip docs/blender.png
"""

import math
import os
import sys
import tempfile

import addon_utils
import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
D = os.path.join(ROOT, "..", "shared", "data", "dt", "horse-camel")
ZIP, OUT = sys.argv[sys.argv.index("--") + 1 :][:2]
POSE = "horse-05"

with tempfile.TemporaryDirectory() as user:
    os.environ["BLENDER_USER_SCRIPTS"] = user
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    addon_utils.enable("meshmorph_blender", default_set=True)
    import meshmorph

    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o)

    def character(name, path, colour, y):
        m = meshmorph.read_mesh(path)
        mesh = bpy.data.meshes.new(name)
        mesh.from_pydata(m.vertices.tolist(), [], m.faces.tolist())
        for p in mesh.polygons:
            p.use_smooth = True
        material = bpy.data.materials.new(name)
        material.use_nodes = True
        material.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = colour
        mesh.materials.append(material)
        obj = bpy.data.objects.new(name, mesh)
        # The files are y-up; Blender is z-up: the object's turn is respected.
        obj.rotation_euler = (math.radians(90), 0, 0)
        obj.location = (0, y, 0)
        bpy.context.scene.collection.objects.link(obj)
        return obj

    horse = character("horse", os.path.join(D, "horse-poses", "horse-reference.obj"), (0.12, 0.27, 0.6, 1), -0.8)
    camel = character("camel", os.path.join(D, "camel-poses", "camel-reference.obj"), (0.6, 0.42, 0.2, 1), 0.8)
    horse.shape_key_add(name="Basis")
    key = horse.shape_key_add(name=POSE)
    key.data.foreach_set("co", meshmorph.read_mesh(os.path.join(D, "horse-poses", POSE + ".obj")).vertices.astype("float32").ravel())
    bpy.context.view_layer.update()
    for o in (horse, camel):
        o.select_set(True)
    bpy.context.view_layer.objects.active = camel
    s = bpy.context.scene.meshmorph
    s.marker_source, s.marker_file = "FILE", os.path.join(D, "markers", "horse-camel-107.cons")
    assert bpy.ops.meshmorph.transfer_shape_keys() == {"FINISHED"}
    horse.data.shape_keys.key_blocks[POSE].value = 1.0
    camel.data.shape_keys.key_blocks[POSE].value = 1.0

    scene = bpy.context.scene
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    camera.data.type = "ORTHO"
    camera.data.ortho_scale = 3.2
    camera.location = (4, 0.12, 0.45)
    camera.rotation_euler = (math.radians(90), 0, math.radians(90))
    scene.collection.objects.link(camera)
    scene.camera = camera
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 2.2
    sun.rotation_euler = (math.radians(40), math.radians(35), math.radians(60))
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.9, 0.9, 0.92, 1)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.samples = 64
    scene.cycles.use_denoising = False
    scene.cycles.device = "CPU"
    scene.render.resolution_x, scene.render.resolution_y = 960, 420
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.render.filepath = os.path.abspath(OUT)
    bpy.ops.render.render(write_still=True)
