// The README's screenshot of the run viewer, taken over the DevTools protocol: the viewport is
// set to WIDTH × HEIGHT before the page loads (Chromium's --screenshot mode resizes the viewport
// after the page has laid out, which left the 3-D scene shorter than its box), the page is
// opened, and the screenshot is taken once both panels are drawn and the selection has settled.
// Used by scripts/plot_screenshot.sh; needs only node (≥ 18) and Chromium (scripts/cdp.mjs).
//
//   node scripts/plot_screenshot.mjs CHROMIUM URL OUT.png [WIDTH HEIGHT]
import { writeFileSync } from 'node:fs';
import { openPage, sleep } from './cdp.mjs';

const [chromium, url, outPng, width = '1400', height = '1000'] = process.argv.slice(2);
const LIMIT_MS = 90000;
(async () => {
  const { send, done, session: s } = await openPage(chromium, width, height);
  await send('Emulation.setDeviceMetricsOverride', { width: Number(width), height: Number(height), deviceScaleFactor: 1, mobile: false }, s);
  await send('Page.navigate', { url }, s);
  const start = Date.now();
  while (Date.now() - start < LIMIT_MS) {
    await sleep(250);
    const r = await send('Runtime.evaluate', {
      expression: 'Boolean(window.__mimo && window.__mimo.marks && window.__mimo.marks.all_drawn_ms)',
      returnByValue: true,
    }, s);
    if (r.result && r.result.result && r.result.result.value === true) break;
  }
  await sleep(3000); // the selection from the URL (#t=…&select=…) and its ellipsoid settle
  const shot = await send('Page.captureScreenshot', { format: 'png' }, s);
  if (!shot.result || !shot.result.data) return done('error: no screenshot');
  writeFileSync(outPng, Buffer.from(shot.result.data, 'base64'));
  done(`wrote ${outPng}`);
})();
