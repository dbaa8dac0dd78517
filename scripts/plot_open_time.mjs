// Open a run viewer page in headless Chromium and wait for its self-test verdict, over the
// DevTools protocol on a pipe (no --dump-dom: headless Chromium dumps the DOM at a moment of its
// own choosing, which may come before the page's first render). Prints one JSON line:
// {marks, verdict} (verdict null when the self-test did not finish within the time limit).
// Used by scripts/plot_open_time.sh; needs only node (≥ 18) and Chromium.
//
//   node scripts/plot_open_time.mjs CHROMIUM URL [TIMEOUT_MS]
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

const [chromium, url, limit = '90000'] = process.argv.slice(2);
const profile = mkdtempSync(join(tmpdir(), 'mimo-plot-'));
const args = ['--headless', '--no-sandbox', '--disable-gpu', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync',
  '--disable-extensions', '--host-resolver-rules=MAP * ~NOTFOUND', '--window-size=1400,1000',
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
  process.stdout.write(JSON.stringify(result) + '\n');
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
  await send('Page.navigate', { url }, s);
  const start = Date.now();
  let marks = null;
  while (Date.now() - start < Number(limit)) {
    await sleep(250);
    const r = await send('Runtime.evaluate', {
      expression: 'JSON.stringify({m: window.__mimo && window.__mimo.marks, v: (document.getElementById("selftest") || {}).textContent || ""})',
      returnByValue: true,
    }, s);
    const v = r.result && r.result.result && JSON.parse(r.result.result.value || '{}');
    if (!v) continue;
    marks = v.m;
    if (v.v && v.v.startsWith('MIMO-SELFTEST ')) return done({ marks, verdict: JSON.parse(v.v.slice(14)) });
  }
  done({ marks, verdict: null });
})();
