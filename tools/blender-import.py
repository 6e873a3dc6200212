"""Imports a `arbor export --game` file into Blender (headless) and checks what Blender
made of it: the level nodes (NAME_LOD0..n), the armature and its bones, the wind action
and its frames, and that every level's mesh is skinned to the armature (an Armature
modifier and a vertex group a bone). Prints one line a finding and exits non-zero when
something is missing.

Run through tools/blender-import: blender -b -P tools/blender-import.py -- IN.glb
"""
import sys

import bpy
import numpy

# Debian's Blender 3.4 imports glTF skins with `numpy.bool`, which numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

src = sys.argv[sys.argv.index("--") + 1:][0]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
objects = list(bpy.context.scene.objects)
problems = []

levels = sorted(o.name for o in objects if "_LOD" in o.name and o.type == "MESH")
print(f"levels: {len(levels)}: {', '.join(levels)}")
if len(levels) < 2:
    problems.append("fewer than two level nodes")

others = sorted(o.name for o in objects if o.type == "MESH" and o.name not in levels)
print(f"other meshes: {len(others)}: {', '.join(others[:6])}{' ...' if len(others) > 6 else ''}")

armatures = [o for o in objects if o.type == "ARMATURE"]
bones = len(armatures[0].data.bones) if armatures else 0
print(f"armatures: {len(armatures)}, bones: {bones}")
if len(armatures) != 1 or bones < 2:
    problems.append("no armature with bones")

for name in levels:
    o = bpy.context.scene.objects[name]
    skinned = any(m.type == "ARMATURE" and m.object in armatures for m in o.modifiers)
    groups = len(o.vertex_groups)
    print(f"{name}: {len(o.data.vertices)} vertices, {len(o.data.polygons)} faces, "
          f"armature modifier: {skinned}, vertex groups: {groups}")
    # The impostor and billboard levels are cards: not skinned.
    if len(o.data.polygons) > 64 and (not skinned or groups == 0):
        problems.append(f"{name} is not skinned")

actions = list(bpy.data.actions)
for a in actions:
    lo, hi = a.frame_range
    rotations = sum(1 for c in a.fcurves if c.data_path.endswith("rotation_quaternion"))
    print(f"action {a.name}: frames {lo:.0f}..{hi:.0f}, {len(a.fcurves)} curves, "
          f"{rotations // 4} bones rotated")
if not actions or max(a.frame_range[1] - a.frame_range[0] for a in actions) < 2:
    problems.append("no action with frames")

# The armature moves the tree: a bone's pose at a quarter of the clip is not its rest.
if armatures and actions:
    arm = armatures[0]
    scene = bpy.context.scene
    lo, hi = actions[0].frame_range
    scene.frame_set(int(lo))
    rest = {b.name: b.matrix.copy() for b in arm.pose.bones}
    scene.frame_set(int(lo + (hi - lo) / 4))
    moved = sum(1 for b in arm.pose.bones if (b.matrix.col[3] - rest[b.name].col[3]).length > 1e-5
                or (b.matrix.to_quaternion().rotation_difference(rest[b.name].to_quaternion())).angle > 1e-4)
    print(f"bones posed away from frame {lo:.0f} at frame {lo + (hi - lo) / 4:.0f}: {moved} of {bones}")
    if moved == 0:
        problems.append("the action moves no bone")

for p in problems:
    print(f"problem: {p}")
print("blender import: " + ("ok" if not problems else f"{len(problems)} problems"))
sys.exit(1 if problems else 0)
