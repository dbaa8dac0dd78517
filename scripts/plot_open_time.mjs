// Open a run viewer page in headless Chromium and wait for its self-test verdict, over the
// DevTools protocol on a pipe (no --dump-dom: headless Chromium dumps the DOM at a moment of its
// own choosing, which may come before the page's first render). Prints one JSON line:
// {marks, verdict} (verdict null when the self-test did not finish within the time limit).
// Used by scripts/plot_open_time.sh; needs only node (≥ 18) and Chromium (scripts/cdp.mjs).
//
//   node scripts/plot_open_time.mjs CHROMIUM URL [TIMEOUT_MS]
import { openPage, sleep } from './cdp.mjs';

const [chromium, url, limit = '90000'] = process.argv.slice(2);
(async () => {
  const { send, done, session: s } = await openPage(chromium);
  const finish = (result) => done(JSON.stringify(result));
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
    if (v.v && v.v.startsWith('MIMO-SELFTEST ')) return finish({ marks, verdict: JSON.parse(v.v.slice(14)) });
  }
  finish({ marks, verdict: null });
})();
