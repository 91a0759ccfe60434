// Opens lumiere's page in headless Chromium (puppeteer-core drives Debian's
// chromium), waits until the viewer says on the console that it reached the
// samples per pixel of the page's `spp=` and writes a screenshot; prints
// every console line and page error, then "lumiere-check: ok" or fails.
// With LUMIERE_DROP=FILE it then drops FILE on the page, as a user drops a
// glTF file, and waits for the page to report again, on the new scene.
//
//   node tests/web/check.mjs URL SCREENSHOT.png [TIMEOUT_SECONDS]
//
// LUMIERE_NODE_MODULES names the folder whose node_modules holds
// puppeteer-core (`npm install --prefix FOLDER puppeteer-core`).
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
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
const drop = process.env.LUMIERE_DROP;
let reached = null;
let reports = 0;
const lines = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800, deviceScaleFactor: 1 });
  page.on('console', (message) => {
    const line = `${message.type()}: ${message.text()}`;
    lines.push(line);
    if (message.text().startsWith('lumiere: reached')) {
      reports += 1;
      reached = message.text();
    }
  });
  page.on('pageerror', (error) => lines.push(`pageerror: ${error.message}\n${error.stack ?? ''}`));
  const started = Date.now();
  await page.goto(url, { waitUntil: 'load' });
  const wait = async (count) => {
    while (reports < count && Date.now() - started < Number(timeout) * 1000) {
      await new Promise((resolve) => setTimeout(resolve, 250));
    }
  };
  await wait(1);
  if (drop && reports === 1) {
    // a drop event carrying the file, on the canvas, as a browser sends it
    const bytes = [...readFileSync(drop)];
    await page.evaluate((name, data) => {
      const transfer = new DataTransfer();
      transfer.items.add(new File([new Uint8Array(data)], name));
      const canvas = document.getElementById('lumiere');
      for (const type of ['dragenter', 'dragover', 'drop']) {
        canvas.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
      }
    }, basename(drop), bytes);
    lines.push(`dropped ${basename(drop)}`);
    await wait(2);
  }
  if (reports < (drop ? 2 : 1)) reached = null;
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
