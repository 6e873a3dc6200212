"""Renders a glTF/GLB file with Blender (headless, Cycles on the CPU) from a fixed camera
and light, so trees can be judged by eye and compared with other tools' trees.

Run through tools/render: blender -b -P tools/render-blender.py -- IN OUT.png SIZE SAMPLES
The camera looks at the model from the side (from -Y in Blender's Z-up space, 6 degrees
above), framing what stands above the ground with a margin; a sun from the front left and
a pale sky light it; a grey ground plane sits at height 0 (under the model when it does
not reach below 0). Nothing depends on the file but its bounds.
"""
import math
import sys

import bpy
import mathutils
import numpy

# Debian's Blender 3.4 imports glTF with `numpy.bool`, which numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

argv = sys.argv[sys.argv.index("--") + 1:]
src, out = argv[0], argv[1]
size = int(argv[2]) if len(argv) > 2 else 640
samples = int(argv[3]) if len(argv) > 3 else 32

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
bpy.ops.import_scene.gltf(filepath=src)
meshes = [o for o in scene.objects if o.type == "MESH"]
if not meshes:
    sys.exit(f"{src}: no meshes")
points = [o.matrix_world @ mathutils.Vector(c) for o in meshes for c in o.bound_box]
lo = mathutils.Vector([min(p[k] for p in points) for k in range(3)])
hi = mathutils.Vector([max(p[k] for p in points) for k in range(3)])
center = (lo + hi) / 2
extent = hi - lo

# Ground: at height 0 when the model reaches below it (a tree's roots sink into the
# ground its trunk stands on), else under the model.
ground_z = 0.0 if lo.z < 0.0 < hi.z else lo.z
bpy.ops.mesh.primitive_plane_add(size=max(extent.x, extent.y, extent.z) * 6,
                                 location=(center.x, center.y, ground_z))
ground = bpy.context.active_object
gm = bpy.data.materials.new("ground")
gm.use_nodes = True
gm.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.32, 0.30, 0.26, 1)
gm.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 1.0
ground.data.materials.append(gm)

# Camera: from the side, a little above the middle of the tree, framing its height and width.
cam_data = bpy.data.cameras.new("camera")
cam_data.lens = 50
cam = bpy.data.objects.new("camera", cam_data)
scene.collection.objects.link(cam)
fov = cam_data.angle
span = max(hi.z - ground_z, extent.x, extent.y) * 1.12
dist = span / 2 / math.tan(fov / 2)
elev = math.radians(6)
target = mathutils.Vector((center.x, center.y, ground_z + (hi.z - ground_z) * 0.5))
cam.location = target + mathutils.Vector((0, -dist * math.cos(elev), dist * math.sin(elev)))
cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
cam_data.clip_end = dist * 10
scene.camera = cam

# Light: a sun from the front left, above; a pale sky.
sun_data = bpy.data.lights.new("sun", "SUN")
sun_data.energy = 3.5
sun_data.angle = math.radians(3)
sun = bpy.data.objects.new("sun", sun_data)
sun.rotation_euler = (math.radians(50), 0, math.radians(-35))
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.62, 0.74, 0.90, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.9
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.cycles.max_bounces = 4
scene.cycles.transparent_max_bounces = 16
scene.render.resolution_x = size
scene.render.resolution_y = size
scene.render.film_transparent = False
scene.view_settings.view_transform = "Filmic"
scene.render.image_settings.file_format = "PNG"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
images = [i for i in bpy.data.images if i.size[0] > 0]
print(f"rendered {src} -> {out}: {len(meshes)} meshes, {len(images)} textures, "
      f"{extent.z:.2f} m tall, {extent.x:.2f} x {extent.y:.2f} m wide")
