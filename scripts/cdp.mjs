// Headless Debian Chromium driven over the DevTools protocol on a pipe (no port, no network:
// every host name resolves to nothing), shared by scripts/plot_open_time.mjs and
// scripts/plot_screenshot.mjs. Needs only node (≥ 18) and Chromium.
//
//   const c = await openPage(chromium, width, height);   // a page target, attached
//   await c.send('Page.navigate', { url }, c.session);
//   c.done(line);                                         // print the line, close, clean up, exit
import { spawn } from 'node:child_process';
import { mkdtempSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join } from 'node:path';

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

export async function openPage(chromium, width = 1400, height = 1000) {
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
  function done(line) {
    process.stdout.write(line + '\n');
    send('Browser.close').catch(() => {});
    const clean = () => {
      try { rmSync(profile, { recursive: true, force: true }); } catch (e) { /* Chromium may still be writing it */ }
      process.exit(0);
    };
    chrome.on('exit', clean);
    setTimeout(() => { chrome.kill(); setTimeout(clean, 1000); }, 2000);
  }
  const targets = await send('Target.getTargets');
  const page = targets.result.targetInfos.find((t) => t.type === 'page');
  const att = await send('Target.attachToTarget', { targetId: page.targetId, flatten: true });
  return { send, done, session: att.result.sessionId };
}
