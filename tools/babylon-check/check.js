// Loads a wildlod LOD chain (one GLB with MSFT_lod) in Babylon.js in
// headless Chromium, the way a web viewer streams it: from a loopback HTTP
// server that answers Range requests, with the glTF loader's
// `useRangeRequests`, so Babylon fetches the coarsest level first and each
// finer one after it (MSFT_lod progressive loading).
//
//   node check.js CHAIN.glb [SHOTS]
//
// With SHOTS, a screenshot of every run is saved as SHOTS_all.png (every
// level loaded) and SHOTS_maxK.png.
//
// For every `maxLODsToLoad` from 1 to the number of levels, and once with
// the default (all levels), it records, each time a level has loaded, the
// enabled meshes (name, triangles drawn) and at the end the console errors,
// page errors and failed requests; it prints one JSON line:
//   {"levels": N, "errors": [...], "runs": [{"maxLODs": k (null: all),
//     "complete": bool, "events": [{"lod": i, "meshes": [[name, triangles],
//     ...], "triangles": t}], "final": {"meshes", "triangles"},
//     "ranges": [[first byte, last byte] or null for the whole file, ...],
//     "errors": [...]}]}
// Events count levels from the coarsest (0) as Babylon does.
// The browser is the system's (CHROMIUM or /usr/bin/chromium).
const { chromium } = require('playwright-core');
const fs = require('fs');
const http = require('http');
const path = require('path');

const [chain, shot] = process.argv.slice(2);
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';
const modules = path.join(__dirname, 'node_modules');

const PAGE = `<!doctype html>
<html><head><meta charset="utf-8"><link rel="icon" href="data:,">
<script type="importmap">{"imports": {
  "@babylonjs/core/": "/node_modules/@babylonjs/core/",
  "@babylonjs/loaders/": "/node_modules/@babylonjs/loaders/"
}}</script>
<style>html, body, canvas { margin: 0; width: 100%; height: 100%; display: block; }</style>
</head><body><canvas id="c"></canvas>
<script type="module">
import { Engine } from '@babylonjs/core/Engines/engine.js';
import { Scene } from '@babylonjs/core/scene.js';
import { ArcRotateCamera } from '@babylonjs/core/Cameras/arcRotateCamera.js';
import { HemisphericLight } from '@babylonjs/core/Lights/hemisphericLight.js';
import { Vector3 } from '@babylonjs/core/Maths/math.vector.js';
import { Color4 } from '@babylonjs/core/Maths/math.color.js';
import '@babylonjs/core/Loading/loadingScreen.js';
import { AppendSceneAsync, SceneLoader } from '@babylonjs/core/Loading/sceneLoader.js';
import '@babylonjs/loaders/glTF/glTFFileLoader.js';
import '@babylonjs/loaders/glTF/2.0/index.js';

// No loading overlay: the screenshot shows the model.
SceneLoader.ShowLoadingScreen = false;
const canvas = document.getElementById('c');
const engine = new Engine(canvas, true, { preserveDrawingBuffer: true });

// Triangles of every mesh the scene would draw now.
function drawn(scene) {
  const meshes = scene.meshes
    .filter((m) => m.isEnabled() && m.isVisible && m.getTotalIndices && m.getTotalIndices() > 0)
    .map((m) => [m.name, m.getTotalIndices() / 3]);
  meshes.sort((a, b) => (a[0] < b[0] ? -1 : a[0] > b[0] ? 1 : 0));
  return { meshes, triangles: meshes.reduce((s, m) => s + m[1], 0) };
}

window.loadChain = async (url, maxLODs) => {
  const scene = new Scene(engine);
  scene.clearColor = new Color4(1, 1, 1, 1);
  const camera = new ArcRotateCamera('camera', 0.8, 1.1, 10, Vector3.Zero(), scene);
  new HemisphericLight('light', new Vector3(0.3, 1, 0.2), scene);
  const events = [];
  const options = { useRangeRequests: true };
  if (maxLODs) options.extensionOptions = { MSFT_lod: { maxLODsToLoad: maxLODs } };
  let complete;
  const completed = new Promise((resolve, reject) => { complete = { resolve, reject }; });
  // The loader's own observables (the options object does not take them).
  SceneLoader.OnPluginActivatedObservable.addOnce((loader) => {
    loader.onExtensionLoadedObservable.add((ext) => {
      if (ext.name === 'MSFT_lod') {
        ext.onNodeLODsLoadedObservable.add((lod) => events.push({ lod, ...drawn(scene) }));
      }
    });
    loader.onCompleteObservable.add(() => complete.resolve(true));
    loader.onErrorObservable.add((e) => complete.reject(e));
  });
  await AppendSceneAsync(url, scene, { pluginOptions: { gltf: options } });
  const done = await Promise.race([completed, new Promise((r) => setTimeout(() => r(false), 60000))]);
  scene.stopAllAnimations();
  camera.setTarget(Vector3.Zero());
  const extent = scene.getWorldExtends((m) => m.isEnabled() && m.getTotalVertices() > 0);
  const center = extent.min.add(extent.max).scale(0.5);
  camera.setTarget(center);
  camera.radius = extent.max.subtract(extent.min).length() * 1.1;
  await scene.whenReadyAsync();
  engine.runRenderLoop(() => scene.render());
  const final = drawn(scene);
  window.lastScene = scene;
  return { complete: done, events, final };
};
window.babylonReady = true;
</script></body></html>`;

let ranges = [];

function serve(req, res) {
  const url = decodeURIComponent(req.url.split('?')[0]);
  let file;
  let type = 'application/octet-stream';
  if (url === '/' || url === '/index.html') {
    res.writeHead(200, { 'Content-Type': 'text/html' });
    res.end(PAGE);
    return;
  } else if (url === '/chain.glb') {
    file = path.resolve(chain);
    type = 'model/gltf-binary';
  } else if (url.startsWith('/node_modules/')) {
    file = path.join(modules, path.normalize(url.slice('/node_modules/'.length)));
    if (!file.startsWith(modules)) file = null;
    if (file && file.endsWith('.js')) type = 'text/javascript';
  }
  if (!file || !fs.existsSync(file) || !fs.statSync(file).isFile()) {
    res.writeHead(404);
    res.end();
    return;
  }
  const size = fs.statSync(file).size;
  const range = req.headers.range;
  if (url === '/chain.glb' && range) {
    const m = /^bytes=(\d+)-(\d*)$/.exec(range);
    const start = m ? Number(m[1]) : NaN;
    const end = m && m[2] !== '' ? Math.min(Number(m[2]), size - 1) : size - 1;
    if (!m || start > end || start >= size) {
      ranges.push(['bad', range]);
      res.writeHead(416, { 'Content-Range': `bytes */${size}` });
      res.end();
      return;
    }
    ranges.push([start, end]);
    res.writeHead(206, {
      'Content-Type': type,
      'Accept-Ranges': 'bytes',
      'Content-Range': `bytes ${start}-${end}/${size}`,
      'Content-Length': end - start + 1,
    });
    fs.createReadStream(file, { start, end }).pipe(res);
    return;
  }
  if (url === '/chain.glb') ranges.push(null);
  res.writeHead(200, { 'Content-Type': type, 'Content-Length': size, 'Accept-Ranges': 'bytes' });
  fs.createReadStream(file).pipe(res);
}

function levelCount(file) {
  const d = fs.readFileSync(file);
  const len = d.readUInt32LE(12);
  const gltf = JSON.parse(d.subarray(20, 20 + len).toString('utf8'));
  let most = 0;
  for (const n of gltf.nodes || []) {
    const ids = n.extensions && n.extensions.MSFT_lod && n.extensions.MSFT_lod.ids;
    if (ids) most = Math.max(most, ids.length + 1);
  }
  return most;
}

(async () => {
  const out = { levels: 0, runs: [], errors: [] };
  const server = http.createServer(serve);
  await new Promise((r) => server.listen(0, '127.0.0.1', r));
  const base = `http://127.0.0.1:${server.address().port}`;
  let browser;
  try {
    out.levels = levelCount(chain);
    browser = await chromium.launch({
      executablePath,
      headless: true,
      args: [
        '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
        '--disable-background-networking', '--disable-component-update', '--disable-sync',
        '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      ],
    });
    const limits = [];
    for (let k = 1; k <= out.levels; k++) limits.push(k);
    limits.push(null);
    for (const maxLODs of limits) {
      ranges = [];
      const run = { maxLODs, complete: false, events: [], final: null, ranges, errors: [] };
      const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
      page.on('console', (m) => { if (m.type() === 'error') run.errors.push(`console: ${m.text()}`); });
      page.on('pageerror', (e) => run.errors.push(`page: ${e.message}`));
      page.on('requestfailed', (r) => run.errors.push(`request failed: ${r.url().slice(0, 80)}`));
      try {
        await page.goto(base + '/', { waitUntil: 'load', timeout: 120000 });
        await page.waitForFunction(() => window.babylonReady === true, null, { timeout: 120000 });
        const r = await page.evaluate(([u, k]) => window.loadChain(u, k), [base + '/chain.glb', maxLODs]);
        Object.assign(run, r);
        if (shot) {
          await page.waitForTimeout(300);
          await page.screenshot({ path: `${shot}_${maxLODs === null ? 'all' : 'max' + maxLODs}.png` });
        }
      } catch (e) {
        run.errors.push(`load: ${String(e.message || e).split('\n')[0]}`);
      }
      await page.close();
      out.runs.push(run);
    }
  } catch (e) {
    out.errors.push(`browser: ${String(e).split('\n')[0]}`);
  } finally {
    if (browser) await browser.close();
    server.close();
  }
  console.log(JSON.stringify(out));
})();
