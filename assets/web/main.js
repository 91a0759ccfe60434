// Starts lumiere's viewer on the page: the WebAssembly module, rayon's pool
// of Web Workers, then the viewer on the canvas. Any failure is written on
// the page, never a blank canvas.
//
// Web Workers share the module's memory, which a browser allows only on a
// cross-origin-isolated page (`lumiere serve` sends the two headers). Any
// other page loads the module built for one thread, which renders between
// frames, and says so.

const status = document.getElementById('status');
const notice = document.getElementById('notice');

function fail(message) {
  status.className = 'error';
  status.textContent = message;
  status.hidden = false;
  console.error(message);
}

window.addEventListener('error', (event) => fail(`lumiere stopped: ${event.message}`));
window.addEventListener('unhandledrejection', (event) => fail(`lumiere stopped: ${event.reason}`));

async function main() {
  const isolated = self.crossOriginIsolated;
  const module = await import(isolated ? './pkg/lumiere.js' : './pkg-one-thread/lumiere.js');
  await module.default();
  if (isolated) {
    // the cores render; one more worker runs the viewer's progressive loop
    // (`?threads=N` sets the number of workers)
    const asked = Number(new URLSearchParams(location.search).get('threads'));
    const threads = asked >= 1 ? Math.min(asked, 64)
      : Math.max(1, navigator.hardwareConcurrency || 1) + 1;
    await module.initThreadPool(threads);
    console.log(`lumiere: ${threads} Web Workers`);
  } else {
    console.log('lumiere: one thread (the page is not cross-origin isolated)');
    notice.firstElementChild.textContent = 'This page is not cross-origin isolated, so lumiere renders on one thread, ' +
      'between frames. Serve the folder with `lumiere serve FOLDER` to render on every core.';
    notice.hidden = false;
  }
  status.hidden = true;
  await module.start('lumiere');
}

main().catch((error) => fail(`lumiere could not start: ${error}`));
