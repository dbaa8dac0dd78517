// The README's screenshot of the run viewer, taken over the DevTools protocol: the viewport is
// set to WIDTH × HEIGHT before the page loads (Chromium's --screenshot mode resizes the viewport
// after the page has laid out, which left the 3-D scene shorter than its box), the page is
// opened, and the screenshot is taken once both panels are drawn and the selection has settled.
// Used by scripts/plot_screenshot.sh; needs only node (≥ 18) and Chromium.
//
//   node scripts/plot_screenshot.mjs CHROMIUM URL OUT.png [WIDTH HEIGHT]
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

import { writeFileSync } from 'node:fs';
const [chromium, url, out_png, width = '1400', height = '1000'] = process.argv.slice(2);
const limit = 90000;
const profile = mkdtempSync(join(tmpdir(), 'mimo-plot-'));
const args = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--disable-extensions', '--host-resolver-rules=MAP * ~NOTFOUND', `--window-size=${width},${height}`,
  `--user-data-dir=${profile}`, '--remote-debugging-pipe', 'about:blank'];
const chrome = spawn(chromium, args, { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });
const out = chrome.stdio[3], inp = chrome.stdio[4];
let id = 0, buf = '';
const waiting = new Map();
inp.on('data', (d) => {
  buf += d.toString();
  let k;
  while ((k = buf.indexOf('\0')) >= 0) {
    const msg = JSON.parse(buf.slice(0, k));
    buf = buf.slice(k + 1);
    if (msg.id && waiting.has(msg.id)) { waiting.get(msg.id)(msg); waiting.delete(msg.id); }
  }
});
function send(method, params = {}, sessionId) {
  const m = { id: ++id, method, params };
  if (sessionId) m.sessionId = sessionId;
  out.write(JSON.stringify(m) + '\0');
  return new Promise((r) => waiting.set(m.id, r));
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
function done(result) {
  process.stdout.write(String(result) + '\n');
  send('Browser.close').catch(() => {});
  const clean = () => {
    try { rmSync(profile, { recursive: true, force: true }); } catch (e) { /* Chromium may still be writing it */ }
    process.exit(0);
  };
  chrome.on('exit', clean);
  setTimeout(() => { chrome.kill(); setTimeout(clean, 1000); }, 2000);
}
(async () => {
  const targets = await send('Target.getTargets');
  const page = targets.result.targetInfos.find((t) => t.type === 'page');
  const att = await send('Target.attachToTarget', { targetId: page.targetId, flatten: true });
  const s = att.result.sessionId;
  await send('Emulation.setDeviceMetricsOverride', { width: Number(width), height: Number(height), deviceScaleFactor: 1, mobile: false }, s);
  await send('Page.navigate', { url }, s);
  const start = Date.now();
  while (Date.now() - start < limit) {
    await sleep(250);
    const r = await send('Runtime.evaluate', {
      expression: 'Boolean(window.__mimo && window.__mimo.marks && window.__mimo.marks.all_drawn_ms)',
      returnByValue: true,
    }, s);
    if (r.result && r.result.result && r.result.result.value === true) break;
  }
  await sleep(3000); // the selection from the URL (#t=…&select=…) and its ellipsoid settle
  const shot = await send('Page.captureScreenshot', { format: 'png' }, s);
  if (!shot.result || !shot.result.data) { done('error: no screenshot'); return; }
  writeFileSync(out_png, Buffer.from(shot.result.data, 'base64'));
  done(`wrote ${out_png}`);
})();
