// Opens a wildlod report in headless Chromium, waits until its viewers
// have drawn, saves a screenshot of the two views (SHOT), then works the
// page as a user would: clicks each look (textured, error heat map,
// wireframe) and saves each view's canvas (SHOT_<look>_left.png,
// SHOT_<look>_right.png); with a level slider, steps through the levels
// with the arrow keys in wireframe (SHOT_level<k>_right.png). Prints one
// JSON line: {"ready": bool, "errors": [console errors and page errors],
// "default_mode": the look shown first, "modes": [{mode, checked}],
// "levels": [{value, label, right_label}]}.
// The browser is the system's (CHROMIUM or /usr/bin/chromium): Playwright
// never downloads one here, and gives it a fresh temporary profile.
const { chromium } = require('playwright-core');
const path = require('path');

// node check.js REPORT SHOT [--page PAGE.png [--look LOOK] [--level K]]:
// --page also saves the whole page in a look and at a level (for docs).
const [report, shot, ...rest] = process.argv.slice(2);
const option = (name) => {
  const i = rest.indexOf(name);
  return i >= 0 ? rest[i + 1] : undefined;
};
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';

// Two animation frames: the page renders on the next one.
const frames = (page) => page.evaluate(() => new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r))));

async function states(page, base, out) {
  out.default_mode = await page.evaluate(() => {
    const on = document.querySelector('#mode input:checked');
    return on ? on.value : null;
  });
  for (const mode of ['textured', 'heat', 'wire']) {
    await page.click(`label[for=mode-${mode}]`);
    await frames(page);
    const checked = await page.isChecked(`#mode-${mode}`);
    await page.locator('#left canvas').screenshot({ path: `${base}_${mode}_left.png` });
    await page.locator('#right canvas').screenshot({ path: `${base}_${mode}_right.png` });
    out.modes.push({ mode, checked });
  }
  if (!(await page.isVisible('#level'))) return;
  await page.click('label[for=mode-wire]');
  const max = Number(await page.getAttribute('#level', 'max'));
  await page.focus('#level');
  await page.keyboard.press('Home');
  for (let k = 0; k <= max; k++) {
    if (k > 0) await page.keyboard.press('ArrowRight');
    await frames(page);
    await page.locator('#right canvas').screenshot({ path: `${base}_level${k}_right.png` });
    out.levels.push({
      value: Number(await page.inputValue('#level')),
      label: await page.textContent('#level-label'),
      right_label: await page.textContent('#right-label'),
    });
  }
}

(async () => {
  const errors = [];
  const out = { default_mode: null, modes: [], levels: [] };
  let ready = false;
  let browser;
  try {
    browser = await chromium.launch({
      executablePath,
      headless: true,
      args: [
        '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
        '--disable-background-networking', '--disable-component-update', '--disable-sync',
        // WebGL without a GPU: SwiftShader, which Chromium ships.
        '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
      ],
    });
    const page = await browser.newPage({ viewport: { width: 1200, height: 800 } });
    page.setDefaultTimeout(60000);
    page.on('console', (m) => { if (m.type() === 'error') errors.push(`console: ${m.text()}`); });
    // A script error means the page will never be ready: stop waiting.
    const crashed = new Promise((_, reject) => page.on('pageerror', (e) => {
      errors.push(`page: ${e.message}`);
      reject(new Error('the page threw'));
    }));
    crashed.catch(() => {});
    page.on('requestfailed', (r) => errors.push(`request failed: ${r.url().slice(0, 80)}`));
    await page.goto('file://' + path.resolve(report), { waitUntil: 'load', timeout: 120000 });
    try {
      await Promise.race([
        page.waitForFunction(() => window.wildlodReady === true, null, { timeout: 120000 }),
        crashed,
      ]);
      ready = true;
      // Let the first animation frames draw.
      await page.waitForTimeout(500);
    } catch (e) {
      errors.push(`not ready: ${e.message.split('\n')[0]}`);
    }
    await page.locator('#views').screenshot({ path: shot });
    if (ready) await states(page, shot.replace(/\.png$/, ''), out);
    if (ready && option('--page')) {
      await page.click(`label[for=mode-${option('--look') || 'textured'}]`);
      if (option('--level') !== undefined && (await page.isVisible('#level'))) {
        await page.focus('#level');
        await page.keyboard.press('Home');
        for (let k = 0; k < Number(option('--level')); k++) await page.keyboard.press('ArrowRight');
      }
      await frames(page);
      await page.screenshot({ path: option('--page'), fullPage: true });
    }
  } catch (e) {
    errors.push(`browser: ${String(e).split('\n')[0]}`);
  } finally {
    if (browser) await browser.close();
  }
  console.log(JSON.stringify({ ready, errors, ...out }));
})();
