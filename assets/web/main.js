// Starts lumiere's viewer on the page: the WebAssembly module, rayon's pool
// of Web Workers, then the viewer on the canvas. Any failure is written on
// the page, never a blank canvas.
import init, { initThreadPool, start } from './pkg/lumiere.js';

const status = document.getElementById('status');

function fail(message) {
  status.className = 'error';
  status.textContent = message;
  status.hidden = false;
  console.error(message);
}

window.addEventListener('error', (event) => fail(`lumiere stopped: ${event.message}`));
window.addEventListener('unhandledrejection', (event) => fail(`lumiere stopped: ${event.reason}`));

async function main() {
  if (!self.crossOriginIsolated) {
    // shared WebAssembly memory, which the render threads need, exists only
    // on a cross-origin-isolated page
    fail('This page is not cross-origin isolated, so lumiere cannot start its render threads.\n' +
         'Serve the folder with `lumiere serve FOLDER`, which sends the two headers it needs\n' +
         '(Cross-Origin-Opener-Policy: same-origin, Cross-Origin-Embedder-Policy: require-corp).');
    return;
  }
  await init();
  // the cores render; one more worker runs the viewer's progressive loop
  const threads = Math.max(1, navigator.hardwareConcurrency || 1) + 1;
  await initThreadPool(threads);
  console.log(`lumiere: ${threads} Web Workers`);
  status.hidden = true;
  await start('lumiere');
}

main().catch((error) => fail(`lumiere could not start: ${error}`));
