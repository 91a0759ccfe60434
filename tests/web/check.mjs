// Opens lumiere's page in headless Chromium (puppeteer-core drives Debian's
// chromium), waits until the viewer says on the console that it reached the
// samples per pixel of the page's `spp=` and writes a screenshot; prints
// every console line and page error, then "lumiere-check: ok" or fails.
//
//   node tests/web/check.mjs URL SCREENSHOT.png [TIMEOUT_SECONDS]
//
// LUMIERE_NODE_MODULES names the folder whose node_modules holds
// puppeteer-core (`npm install --prefix FOLDER puppeteer-core`).
import { createRequire } from 'node:module';

const require = createRequire(`${process.env.LUMIERE_NODE_MODULES ?? process.cwd()}/`);
const puppeteer = require('puppeteer-core');

const [url, screenshot, timeout = '300'] = process.argv.slice(2);
const browser = await puppeteer.launch({
  executablePath: process.env.CHROMIUM ?? '/usr/bin/chromium',
  headless: true,
  args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
         '--disable-background-networking', '--disable-component-update', '--disable-sync',
         '--no-first-run', '--disable-quic'],
});
let reached = null;
const lines = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800, deviceScaleFactor: 1 });
  page.on('console', (message) => {
    const line = `${message.type()}: ${message.text()}`;
    lines.push(line);
    if (message.text().startsWith('lumiere: reached')) reached = message.text();
  });
  page.on('pageerror', (error) => lines.push(`pageerror: ${error.message}\n${error.stack ?? ''}`));
  const started = Date.now();
  await page.goto(url, { waitUntil: 'load' });
  while (!reached && Date.now() - started < Number(timeout) * 1000) {
    await new Promise((resolve) => setTimeout(resolve, 250));
  }
  const seconds = (Date.now() - started) / 1000;
  // a frame for the last pass
  await new Promise((resolve) => setTimeout(resolve, 500));
  await page.screenshot({ path: screenshot });
  const status = await page.$eval('#status', (e) => (e.hidden ? '' : e.textContent));
  if (status) lines.push(`status: ${status}`);
  lines.push(`lumiere-check: ${reached ? 'reached' : 'timed out'} after ${seconds.toFixed(1)} s`);
} finally {
  await browser.close();
}
for (const line of lines) console.log(line);
console.log(reached ? 'lumiere-check: ok' : 'lumiere-check: failed');
process.exit(reached ? 0 : 1);
