"""Blender's Decimate (Collapse) on a textured file, keeping UVs, materials
and textures: the Blender column of docs/evaluation-appearance.md.

The shared peer harness writes untextured OBJ (it measures geometry); this
imports the file with Blender's own glTF/OBJ importer, adds a Decimate
modifier (Collapse, the given ratio, Blender's defaults otherwise) to every
mesh object and exports a GLB with modifiers applied (armatures excepted:
skins stay skins), so texture metrics can be taken on the result.

usage: ../shared/peers/bpy crates/bench/scripts/blender_decimate_textured.py IN OUT.glb RATIO
"""
import sys
import time

import bpy


def main():
    argv = sys.argv[sys.argv.index('--') + 1:] if '--' in sys.argv else sys.argv[1:]
    inp, out, ratio = argv[0], argv[1], float(argv[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = inp.lower().rsplit('.', 1)[-1]
    if ext in ('gltf', 'glb'):
        bpy.ops.import_scene.gltf(filepath=inp)
    elif ext == 'obj':
        bpy.ops.wm.obj_import(filepath=inp)
    else:
        raise SystemExit(f'unsupported input: {inp}')
    for o in bpy.context.scene.objects:
        if o.type == 'MESH':
            m = o.modifiers.new('decimate', 'DECIMATE')
            m.decimate_type = 'COLLAPSE'
            m.ratio = ratio
    t0 = time.perf_counter()
    bpy.ops.export_scene.gltf(filepath=out, export_format='GLB', export_apply=True)
    print(f'RESULT decimated and exported in {time.perf_counter() - t0:.3f} s')


main()
