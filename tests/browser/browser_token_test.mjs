// Browser test of a station with a token, as a tablet on the shop's network uses it: Debian's
// chromium driven by playwright-core against the real `garmcapd --simulated --token`, replaying
// one rig case. The UI asks for the token once and trades it for an HttpOnly session cookie;
// then the event stream, the live MJPEG preview and the item's photo (none of which can send an
// Authorization header) must all load.
//   node browser_token_test.mjs GARMCAPD WEB_DIR CASE_DIR
// Then the same catalog on a full disk (a small tmpfs, where one can be mounted): the station
// starts read-only, and the UI says so, turns off every write, and still shows the item.
// Prints one line per step and "N passed, N failed"; exits 1 on the first failure.
import { spawn, spawnSync } from 'node:child_process';
import { closeSync, copyFileSync, cpSync, existsSync, mkdtempSync, openSync, rmSync, mkdirSync, writeFileSync, writeSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromium } from 'playwright-core';

const [garmcapd, webDir, rigCase] = process.argv.slice(2);
if (!garmcapd || !webDir || !rigCase) {
  console.error('usage: node browser_token_test.mjs GARMCAPD WEB_DIR CASE_DIR');
  process.exit(2);
}
const CHROMIUM = process.env.GARMCAP_CHROMIUM || '/usr/bin/chromium';
const TOKEN = 'tablet-token-0123456789abcdef';
const JOB_TIMEOUT_MS = 180000;

let passed = 0;
const step = (name) => { passed++; console.log('ok   ' + name); };

function freePort() {
  return new Promise((resolve, reject) => {
    const s = createServer();
    s.unref();
    s.on('error', reject);
    s.listen(0, '127.0.0.1', () => { const { port } = s.address(); s.close(() => resolve(port)); });
  });
}

async function waitFor(fn, ms, what) {
  const end = Date.now() + ms;
  let last;
  while (Date.now() < end) {
    try { const v = await fn(); if (v) return v; } catch (e) { last = e; }
    await new Promise((r) => setTimeout(r, 250));
  }
  throw new Error('timed out waiting for ' + what + (last ? ': ' + last.message : ''));
}

const work = mkdtempSync(join(tmpdir(), 'garmcap-token-'));
const port = await freePort();
const base = `http://127.0.0.1:${port}`;
let daemon = null, context = null, daemonLog = '';

async function startDaemon(dataDir) {
  daemon = spawn(garmcapd, ['--simulated', '--data', dataDir, '--listen', `127.0.0.1:${port}`,
    '--web-dir', webDir, '--token', TOKEN, '--camera', 'replay', '--device', join(work, 'rig')],
  { stdio: ['ignore', 'pipe', 'pipe'] });
  daemon.stdout.on('data', (d) => { daemonLog += d; });
  daemon.stderr.on('data', (d) => { daemonLog += d; });
  await waitFor(async () => (await fetch(base + '/')).ok, 30000, 'garmcapd to answer');
}

async function stopDaemon() {
  const exited = new Promise((r) => daemon.once('exit', r));
  daemon.kill('SIGTERM');
  await exited;
}

// The catalog copied onto a tmpfs that is then filled to the last byte; false where no tmpfs can
// be mounted (not root).
let tmpfsAt = null;
function fullDiskCopyOf(dataDir) {
  const at = join(work, 'small-disk');
  mkdirSync(at);
  if (spawnSync('mount', ['-t', 'tmpfs', '-o', 'size=48m', 'tmpfs', at]).status !== 0) return null;
  tmpfsAt = at;
  cpSync(dataDir, join(at, 'data'), { recursive: true });
  const fd = openSync(join(at, 'filler.bin'), 'w');
  const mb = Buffer.alloc(1 << 20, 7);
  try { for (;;) writeSync(fd, mb); } catch (e) { if (e.code !== 'ENOSPC') throw e; }
  try { for (;;) writeSync(fd, mb.subarray(0, 512)); } catch (e) { if (e.code !== 'ENOSPC') throw e; }
  closeSync(fd);
  return join(at, 'data');
}

async function main() {
  mkdirSync(join(work, 'rig', 'c1'), { recursive: true });
  for (const f of ['empty.png', 'empty.jpg', 'dressed.png', 'dressed.jpg', 'truth.json']) {
    if (existsSync(join(rigCase, f))) copyFileSync(join(rigCase, f), join(work, 'rig', 'c1', f));
  }
  writeFileSync(join(work, 'rig', 'rig.json'), JSON.stringify({
    format: 'garmcap-rig', version: 1,
    cases: [{ id: 'c1', dir: 'c1', type: 'skirt', attributes: {}, hard: false }],
  }));
  await startDaemon(join(work, 'data'));
  if ((await fetch(base + '/api/status')).status !== 401) throw new Error('the API must need the token');
  if ((await fetch(base + '/stream.mjpg')).status !== 401) throw new Error('the preview must need the token');
  step('garmcapd --token answers; the API and the preview refuse a request without it');

  mkdirSync(join(work, 'profile'));
  context = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: CHROMIUM,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    viewport: { width: 768, height: 1024 },
  });
  const page = context.pages()[0] || await context.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  let prompts = 0;
  page.on('dialog', async (d) => { prompts++; await d.accept(TOKEN); });
  const seen = {};  // path -> last HTTP status the browser got
  page.on('response', (r) => {
    const u = new URL(r.url());
    seen[u.pathname.replace(/\/api\/blobs\/.*/, '/api/blobs/*').replace(/\/api\/items\/\d+\/image\/.*/, '/api/items/*/image')] = r.status();
  });

  await page.goto(base + '/#/capture');
  await waitFor(async () => /Form not calibrated/.test(await page.textContent('#banner-title') || ''), 30000, 'the UI to show the station state after the log-in');
  if (prompts !== 1) throw new Error(`the token was asked ${prompts} times, expected once`);
  const cookies = await context.cookies(base);
  const session = cookies.find((c) => c.name === 'garmcap_session');
  if (!session || !session.httpOnly || session.sameSite !== 'Strict')
    throw new Error('expected an HttpOnly SameSite=Strict session cookie, got ' + JSON.stringify(cookies));
  const stored = await page.evaluate(() => JSON.stringify(localStorage));
  if (stored.includes(TOKEN)) throw new Error('the token is kept in localStorage');
  step('the token asked once, traded for an HttpOnly SameSite=Strict cookie; not in the page storage');

  await waitFor(async () => seen['/api/events'] === 200, 15000, 'the event stream to connect with the cookie');
  step('the event stream (EventSource) connects with the cookie');
  await waitFor(async () => page.evaluate(() => {
    const p = document.querySelector('#preview');
    return p && p.naturalWidth > 0;
  }), 20000, 'the live preview to show a frame');
  step('the live MJPEG preview shows frames with the cookie');

  await page.click('#btn-empty');
  await waitFor(async () => !(await page.isDisabled('#btn-capture')), JOB_TIMEOUT_MS, 'calibration (bare-form job)');
  await page.fill('#sku', 'TOK-001');
  await page.click('#btn-capture');
  await waitFor(async () => {
    if (await page.$('#job.failed')) throw new Error('the capture failed: ' + await page.textContent('#job-error'));
    return await page.isVisible('#last') && (await page.textContent('#last-sku')).includes('TOK-001');
  }, JOB_TIMEOUT_MS, 'the capture to finish');
  await waitFor(async () => page.evaluate(() => {
    const img = document.querySelector('#last-img');
    return img && img.complete && img.naturalWidth > 0;
  }), 20000, "the item's photo to load");
  step("bare form and a garment captured; the item's photo loads with the cookie");

  // Logged out, the cookie no longer opens the API.
  const out = await page.evaluate(async () => (await fetch('/api/session', { method: 'DELETE' })).status);
  const after = await page.evaluate(async () => (await fetch('/api/items')).status);
  if (out !== 200 || after !== 401) throw new Error(`log-out: DELETE ${out}, then /api/items ${after}`);
  step('DELETE /api/session logs out: the API answers 401 again');
  if (pageErrors.length) throw new Error('page errors: ' + pageErrors.join('; '));

  await stopDaemon();
  const fullData = fullDiskCopyOf(join(work, 'data'));
  if (!fullData) {
    console.log('skip the read-only station: no tmpfs can be mounted here (needs root)');
    return;
  }
  await startDaemon(fullData);
  const st = await (await fetch(base + '/api/status', { headers: { Authorization: 'Bearer ' + TOKEN } })).json();
  if (st.read_only !== true) throw new Error('expected a read-only start on the full disk: ' + JSON.stringify(st));
  const items = await (await fetch(base + '/api/items', { headers: { Authorization: 'Bearer ' + TOKEN } })).json();
  const id = (items.items || items)[0].id;
  // A new daemon: the page logs in again. Not waiting for "load": the live preview's MJPEG never
  // finishes loading, so that event may never come.
  await page.reload({ waitUntil: 'domcontentloaded' });
  await waitFor(async () => /Read-only/.test(await page.textContent('#banner-title') || ''), 30000,
    'the read-only banner');
  const detail = await page.textContent('#banner-detail');
  if (!/disk is full/.test(detail)) throw new Error('the banner should say why: ' + detail);
  for (const b of ['#btn-capture', '#btn-empty'])
    if (!(await page.isDisabled(b))) throw new Error(b + ' should be off on a read-only station');
  step('full disk: the UI says "Read-only: the disk is full." and both capture buttons are off');
  await page.goto(base + '/#/item/' + id, { waitUntil: 'domcontentloaded' });
  await waitFor(async () => page.evaluate(() => {
    const img = document.querySelector('#photos img');
    return img && img.complete && img.naturalWidth > 0;
  }), 20000, "the item's photo on the read-only station");
  for (const b of ['#f-save', '#btn-delete', '#btn-rerun', '#btn-back'])
    if (!(await page.isDisabled(b))) throw new Error(b + ' should be off on a read-only station');
  step("read-only: the item and its photo are shown; save, delete, re-run and back shot are off");
  if (pageErrors.length) throw new Error('page errors: ' + pageErrors.join('; '));
}

let code = 0;
try {
  await main();
} catch (e) {
  code = 1;
  console.log('FAIL ' + e.message);
  console.log('--- garmcapd log (tail) ---\n' + daemonLog.split('\n').slice(-30).join('\n'));
} finally {
  if (context) await context.close().catch(() => {});
  if (daemon && daemon.exitCode === null) daemon.kill('SIGTERM');
  await new Promise((r) => setTimeout(r, 500));
  if (daemon && daemon.exitCode === null) daemon.kill('SIGKILL');
  if (tmpfsAt) spawnSync('umount', ['-l', tmpfsAt]);
  rmSync(work, { recursive: true, force: true });
}
console.log(`${passed} passed, ${code ? 1 : 0} failed`);
process.exit(code);
