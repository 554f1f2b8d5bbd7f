"""Blender's Decimate (Collapse) on a glTF (or OBJ) file, keeping UVs, materials,
skins and animations, for wildlod's appearance evaluation (a peer, not part
of wildlod).

usage: python-with-bpy decimate_gltf.py INPUT OUTPUT.glb RATIO

The file is imported with merged vertices (glTF stores every seam split;
a user decimating in Blender merges them); every mesh object gets a
Decimate modifier (COLLAPSE, triangulated, Blender's defaults otherwise),
applied before the armature modifier so that skinned meshes keep their
weights; the scene is exported as GLB with animations. Prints the triangle
counts as one JSON line.
"""
import json
import sys

import bpy


def main():
    argv = sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else sys.argv[1:]
    inp, out, ratio = argv[0], argv[1], float(argv[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if inp.lower().endswith('.obj'):
        bpy.ops.wm.obj_import(filepath=inp)
    else:
        # Merged vertices, as a user would decimate: glTF stores seams split.
        bpy.ops.import_scene.gltf(filepath=inp, merge_vertices=True)
    tris_in = tris_out = 0
    for obj in [o for o in bpy.context.scene.objects if o.type == 'MESH']:
        bpy.context.view_layer.objects.active = obj
        if obj.data.users > 1:
            # An instanced mesh: Blender applies modifiers to single users
            # only, so each instance is decimated as its own copy.
            obj.data = obj.data.copy()
        obj.data.calc_loop_triangles()
        tris_in += len(obj.data.loop_triangles)
        mod = obj.modifiers.new('decimate', 'DECIMATE')
        mod.decimate_type = 'COLLAPSE'
        mod.ratio = ratio
        mod.use_collapse_triangulate = True
        # Apply it first: the armature modifier must stay live for export.
        while obj.modifiers[0].name != 'decimate':
            bpy.ops.object.modifier_move_up(modifier='decimate')
        bpy.ops.object.modifier_apply(modifier='decimate')
        obj.data.calc_loop_triangles()
        tris_out += len(obj.data.loop_triangles)
    bpy.ops.export_scene.gltf(filepath=out, export_format='GLB', export_animations=True,
                              export_skins=True, export_apply=False)
    print('RESULT ' + json.dumps({'triangles_in': tris_in, 'triangles_out': tris_out}))


main()
