// Opens lumiere's page in headless Chromium (puppeteer-core drives Debian's
// chromium), waits until the viewer says on the console that it reached the
// samples per pixel of the page's `spp=` and writes a screenshot; prints
// every console line and page error, then "lumiere-check: ok" or fails.
//
//   node tests/web/check.mjs URL SCREENSHOT.png [TIMEOUT_SECONDS]
//
// LUMIERE_ACTIONS, a JSON list, then acts on the page as a user does, each
// action waiting for the page to report again (a new film) unless it saves:
//   {"drop": FILE}    drops FILE on the canvas (a DataTransfer drop event)
//   {"pick": FILE}    presses Ctrl+O and chooses FILE in the file picker
//   {"key": KEY}      presses a key on the canvas ("Digit0" toggles L0)
//   {"reload": true}  reloads the page
//   {"save": N}       presses Ctrl+S and waits for N files in LUMIERE_DOWNLOADS
//   {"click": CSS}    clicks the page's element CSS (not the canvas)
// and {"shot": FILE} in an action writes a screenshot once it is done.
//
// LUMIERE_NODE_MODULES names the folder whose node_modules holds
// puppeteer-core (`npm install --prefix FOLDER puppeteer-core`).
import { readFileSync, readdirSync } from 'node:fs';
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
const actions = JSON.parse(process.env.LUMIERE_ACTIONS ?? '[]');
const downloads = process.env.LUMIERE_DOWNLOADS;
let reached = null;
let failed = null;
let started = Date.now();
let reports = 0;
const lines = [];
try {
  const page = await browser.newPage();
  await page.setViewport({ width: 1280, height: 800, deviceScaleFactor: 1 });
  if (downloads) {
    const session = await page.createCDPSession();
    await session.send('Browser.setDownloadBehavior', { behavior: 'allow', downloadPath: downloads });
  }
  page.on('console', (message) => {
    // with the seconds since the page was asked for
    const line = `${message.type()}: ${message.text()} [${((Date.now() - started) / 1000).toFixed(2)} s]`;
    lines.push(line);
    if (message.text().startsWith('lumiere: reached')) {
      reports += 1;
      reached = message.text();
    }
  });
  page.on('pageerror', (error) => lines.push(`pageerror: ${error.message}\n${error.stack ?? ''}`));
  const pause = (ms) => new Promise((resolve) => setTimeout(resolve, ms));
  const late = () => Date.now() - started > Number(timeout) * 1000;
  started = Date.now();
  await page.goto(url, { waitUntil: 'load' });
  const wait = async (count) => {
    while (reports < count && !late()) await pause(250);
  };
  await wait(1);
  let expected = 1;
  for (const action of actions) {
    if (reports < expected) break;
    if (action.drop) {
      // a drop event carrying the file, on the canvas, as a browser sends it
      const bytes = [...readFileSync(action.drop)];
      await page.evaluate((name, data) => {
        const transfer = new DataTransfer();
        transfer.items.add(new File([new Uint8Array(data)], name));
        const canvas = document.getElementById('lumiere');
        for (const type of ['dragenter', 'dragover', 'drop']) {
          canvas.dispatchEvent(new DragEvent(type, { dataTransfer: transfer, bubbles: true, cancelable: true }));
        }
      }, basename(action.drop), bytes);
      lines.push(`dropped ${basename(action.drop)}`);
    } else if (action.pick) {
      await page.focus('#lumiere');
      const [chooser] = await Promise.all([
        page.waitForFileChooser({ timeout: 10000 }),
        page.keyboard.down('Control').then(() => page.keyboard.press('KeyO')).then(() => page.keyboard.up('Control')),
      ]);
      await chooser.accept([action.pick]);
      lines.push(`picked ${basename(action.pick)}`);
    } else if (action.key) {
      // a click on the viewport's margin gives the canvas the keyboard
      await page.mouse.click(800, 10);
      await page.keyboard.press(action.key);
      lines.push(`pressed ${action.key}`);
    } else if (action.reload) {
      await page.reload({ waitUntil: 'load' });
      lines.push('reloaded');
    } else if (action.click) {
      await page.click(action.click);
      lines.push(`clicked ${action.click}`);
    } else if (action.save) {
      await page.focus('#lumiere');
      await page.keyboard.down('Control');
      await page.keyboard.press('KeyS');
      await page.keyboard.up('Control');
      const done = () => readdirSync(downloads).filter((f) => !f.endsWith('.crdownload'));
      while (done().length < action.save && !late()) await pause(250);
      lines.push(`downloaded ${done().sort().join(' ')}`);
      if (done().length < action.save) failed = `only ${done().length} of ${action.save} files downloaded`;
    }
    if (!action.save && !action.click) {
      expected += 1;
      await wait(expected);
    }
    if (action.shot) {
      await pause(500);
      await page.screenshot({ path: action.shot });
    }
  }
  if (reports < expected) reached = null;
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
if (failed) lines.push(`lumiere-check: ${failed}`);
for (const line of lines) console.log(line);
const ok = reached && !failed;
console.log(ok ? 'lumiere-check: ok' : 'lumiere-check: failed');
process.exit(ok ? 0 : 1);
