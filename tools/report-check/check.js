// Opens a wildlod report in headless Chromium, waits until its viewers
// have drawn, saves a screenshot of the two views and prints one JSON
// line: {"ready": bool, "errors": [console errors and page errors]}.
// The browser is the system's (CHROMIUM or /usr/bin/chromium): Playwright
// never downloads one here, and gives it a fresh temporary profile.
const { chromium } = require('playwright-core');
const path = require('path');

const [report, shot] = process.argv.slice(2);
const executablePath = process.env.CHROMIUM || '/usr/bin/chromium';

(async () => {
  const errors = [];
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
  } catch (e) {
    errors.push(`browser: ${String(e).split('\n')[0]}`);
  } finally {
    if (browser) await browser.close();
  }
  console.log(JSON.stringify({ ready, errors }));
})();
