"""Texture Chamfer (W §5, Table 2) of re-baked LODs against keep-UV,
gltfpack and Blender, on the textured and skinned corpus files: the
"Re-baked textures" table of docs/evaluation-appearance.md.

usage (from the repository root, after `cargo build --release`):
  ../shared/peers/py crates/bench/scripts/evaluate_appearance.py \
      --corpus ../shared/corpus --gltfpack /tmp/gp/node_modules/.bin/gltfpack \
      --out /tmp/appearance.csv

gltfpack 1.3 comes from npm (`npm install gltfpack@1.3` in a scratch
folder); Blender from the peers' environment (../shared/peers/bpy). Every
result is measured by `wildlod compare` against the input (10,000 texture
samples per surface, as W; colors in [0, 1]).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.abspath(os.path.join(HERE, '..', '..', '..'))
WILDLOD = os.path.join(ROOT, 'target', 'release', 'wildlod')
FILES = [
    'textured/Avocado/Avocado.gltf',
    'textured/CesiumMilkTruck.glb',
    'textured/MultiUVTest.glb',
    'textured/bob/bob_tri.obj',
    'textured/sofa_03/sofa_03_1k.gltf',
    'textured/tea_set_01/tea_set_01_1k.gltf',
    'skinned/CesiumMan.glb',
    'skinned/Fox/Fox.gltf',
]


def run(cmd, timeout=3600):
    t0 = time.perf_counter()
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    return p, time.perf_counter() - t0


def compare(ref, cand):
    p, _ = run([WILDLOD, 'compare', ref, cand, '--json', '--samples', '20000'])
    if p.returncode != 0:
        return None
    return json.loads(p.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--corpus', required=True)
    ap.add_argument('--gltfpack', required=True)
    ap.add_argument('--bpy', default=os.path.join(ROOT, '..', 'shared', 'peers', 'bpy'))
    ap.add_argument('--ratios', default='0.5,0.1,0.01')
    ap.add_argument('--work', default='/tmp/wildlod-appearance')
    ap.add_argument('--out', required=True)
    ap.add_argument('--methods', default='keep-UV,re-bake,gltfpack,blender',
                    help='which of keep-UV, re-bake, gltfpack, blender to run')
    ap.add_argument('--compare-only', action='store_true',
                    help='measure the outputs a previous run left in --work again')
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    ratios = [float(r) for r in a.ratios.split(',')]
    rows = []
    for rel in FILES:
        src = os.path.join(a.corpus, rel)
        stem = os.path.splitext(os.path.basename(rel))[0]
        for r in ratios:
            methods = {
                'keep-UV': [WILDLOD, 'simplify', src, '-o', None, '--ratio', str(r), '--overwrite'],
                're-bake': [WILDLOD, 'simplify', src, '-o', None, '--ratio', str(r), '--bake',
                            '--overwrite'],
                'gltfpack': [a.gltfpack, '-i', src, '-o', None, '-si', str(r), '-se', '1', '-noq'],
                'blender': [a.bpy, os.path.join(HERE, 'blender_decimate_textured.py'), src, None,
                            str(r)],
            }
            for name, cmd in methods.items():
                if name not in a.methods.split(','):
                    continue
                out = os.path.join(a.work, f'{stem}_{r}_{name}.glb')
                cmd = [out if c is None else c for c in cmd]
                if a.compare_only:
                    p, secs = subprocess.CompletedProcess(cmd, 0 if os.path.exists(out) else 1, '', 'missing'), 0.0
                else:
                    if os.path.exists(out):
                        os.remove(out)
                    p, secs = run(cmd)
                row = {'file': rel, 'ratio': r, 'method': name, 'seconds': round(secs, 2),
                       'status': 'ok', 'triangles': '', 'target': '', 'texture_chamfer': '',
                       'hausdorff': ''}
                if p.returncode != 0 or not os.path.exists(out):
                    row['status'] = 'fail: ' + (p.stderr.strip().splitlines() or ['?'])[-1][:120]
                else:
                    c = compare(src, out)
                    if c is None:
                        row['status'] = 'compare failed'
                    else:
                        row['triangles'] = c['candidate']['triangulated']
                        row['target'] = round(c['reference']['triangulated'] * r)
                        row['texture_chamfer'] = c.get('texture_chamfer')
                        row['hausdorff'] = c.get('hausdorff')
                        if row['triangles'] == 0:
                            row['status'] = 'empty'
                print(row, flush=True)
                rows.append(row)
    with open(a.out, 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


main()
