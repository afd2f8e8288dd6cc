// Browser test of the web UI: Debian's chromium driven by playwright-core against the real
// garmcapd on the simulated rig, on a free loopback port, with a fresh catalog and profile.
//   node browser_test.mjs GARMCAPD WEB_DIR [SCREENSHOT_DIR] [--rig CASE_DIR]
//   node browser_test.mjs --stub WEB_DIR [SCREENSHOT_DIR]   (UI only, against stub_server.mjs)
// --rig: a rig case folder (empty.png or .jpg, dressed.png or .jpg, truth.json, e.g.
// tests/data/rig/case_002)
// that garmcapd replays (--camera replay), so every run sees the same garment; without it the
// daemon's synthetic camera renders random scenes.
// Steps: calibrate (bare form), capture a garment, see it in the last result and the catalog,
// open it, edit the title, see that an item waiting for review is left out of the export, approve
// it, export the Shopify CSV and read the title back from it.
// Prints one line per step and "N passed, N failed"; exits 1 on the first failure.
import { spawn } from 'node:child_process';
import { copyFileSync, existsSync, mkdtempSync, readFileSync, rmSync, mkdirSync, writeFileSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { chromium } from 'playwright-core';
import { parse } from 'csv-parse/sync';

const args = process.argv.slice(2);
let rigCase = null;
const rigAt = args.indexOf('--rig');
if (rigAt >= 0) { rigCase = args[rigAt + 1]; args.splice(rigAt, 2); }
const [garmcapd, webDir, shotDir] = args;
if (!garmcapd || !webDir || (rigAt >= 0 && !rigCase)) {
  console.error('usage: node browser_test.mjs GARMCAPD|--stub WEB_DIR [SCREENSHOT_DIR] [--rig CASE_DIR]');
  process.exit(2);
}
const stub = garmcapd === '--stub';
const CHROMIUM = process.env.GARMCAP_CHROMIUM || '/usr/bin/chromium';
const JOB_TIMEOUT_MS = Number(process.env.GARMCAP_BROWSER_JOB_TIMEOUT_MS || 180000);

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

const work = mkdtempSync(join(tmpdir(), 'garmcap-browser-'));
const port = await freePort();
const base = `http://127.0.0.1:${port}`;
let daemon = null, context = null, daemonLog = '';

async function main() {
  const daemonArgs = ['--simulated', '--data', join(work, 'data'), '--listen', `127.0.0.1:${port}`, '--web-dir', webDir];
  if (rigCase) {
    // A one-case replay rig in the temp folder: the bare form and the dressed frame of CASE_DIR.
    mkdirSync(join(work, 'rig', 'c1'), { recursive: true });
    // Frames as the case holds them, PNG or JPEG (docs/formats.md); the replay camera checks there is one of each.
    for (const f of ['empty.png', 'empty.jpg', 'dressed.png', 'dressed.jpg', 'truth.json']) {
      if (f === 'truth.json' || existsSync(join(rigCase, f))) copyFileSync(join(rigCase, f), join(work, 'rig', 'c1', f));
    }
    // The rig index as capture::readRig reads it (docs/formats.md).
    writeFileSync(join(work, 'rig', 'rig.json'), JSON.stringify({
      format: 'garmcap-rig', version: 1,
      cases: [{ id: 'c1', dir: 'c1', type: 'skirt', attributes: {}, hard: false }],
    }));
    daemonArgs.push('--camera', 'replay', '--device', join(work, 'rig'));
  }
  daemon = stub
    ? spawn(process.execPath, [join(dirname(fileURLToPath(import.meta.url)), 'stub_server.mjs'), String(port), webDir],
      { stdio: ['ignore', 'pipe', 'pipe'] })
    : spawn(garmcapd, daemonArgs, { stdio: ['ignore', 'pipe', 'pipe'] });
  daemon.stdout.on('data', (d) => { daemonLog += d; });
  daemon.stderr.on('data', (d) => { daemonLog += d; });
  daemon.on('exit', (code, sig) => { daemonLog += `\n[garmcapd exited: ${code ?? sig}]\n`; });
  await waitFor(async () => (await fetch(base + '/api/status')).ok, 30000, 'garmcapd to answer');
  step(`${stub ? 'STUB server (not garmcapd)' : 'garmcapd --simulated'} answers on ${base}`);

  mkdirSync(join(work, 'profile'));
  context = await chromium.launchPersistentContext(join(work, 'profile'), {
    executablePath: CHROMIUM,
    headless: true,
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
    viewport: { width: 1280, height: 800 },
    acceptDownloads: true,
  });
  const page = context.pages()[0] || await context.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  const shot = async (name) => {
    if (!shotDir) return;
    // A toast is transient: keep it out of the documentation screenshots.
    await page.evaluate(() => { document.querySelector('#toast').hidden = true; });
    await page.screenshot({ path: join(shotDir, name + '.png') });
  };

  await page.goto(base + '/#/capture');
  await page.waitForSelector('#btn-capture');
  await waitFor(async () => (await page.textContent('#state-text')) !== 'Connecting…', 10000, 'the status');
  step('the capture screen loads and shows the station state: ' + await page.textContent('#state-text'));

  // A fresh station is not calibrated: the UI must say so and offer the bare-form capture.
  const status = await (await fetch(base + '/api/status')).json();
  if (!status.calibrated) {
    const banner = await page.textContent('#banner-title');
    if (!/Form not calibrated/.test(banner || '')) throw new Error('expected the "Form not calibrated" banner, got ' + banner);
    if (!(await page.isDisabled('#btn-capture'))) throw new Error('capture must be disabled before calibration');
    step('uncalibrated: banner "Form not calibrated", capture disabled');
  }
  await shot('capture-uncalibrated');

  await page.click('#btn-empty');
  await waitFor(async () => !(await page.isDisabled('#btn-capture')), JOB_TIMEOUT_MS, 'calibration (bare-form job)');
  step('bare-form capture calibrates the station');

  await page.fill('#sku', 'BRW-001');
  await page.click('#btn-capture');
  await page.waitForSelector('#job:not([hidden])');
  await waitFor(async () => {
    const failed = await page.$('#job.failed');
    if (failed) throw new Error('the capture job failed: ' + await page.textContent('#job-error'));
    return await page.isVisible('#last');
  }, JOB_TIMEOUT_MS, 'the capture to finish');
  const type = await page.textContent('#last-type');
  step('capture finished; last result shows: ' + type.trim());
  await page.waitForTimeout(500);
  await shot('capture-result');

  await page.click('a[data-tab="catalog"]');
  await page.waitForSelector('.tile');
  const tiles = await page.$$('.tile');
  if (tiles.length !== 1) throw new Error('expected 1 item in the catalog, found ' + tiles.length);
  step('the item appears in the catalog grid');
  await page.fill('#search', 'BRW-001');
  await page.waitForTimeout(600);
  if ((await page.$$('.tile')).length !== 1) throw new Error('search by SKU did not find the item');
  await page.fill('#search', 'no-such-thing-xyz');
  await waitFor(async () => (await page.$$('.tile')).length === 0, 5000, 'the search to filter');
  await page.fill('#search', '');
  await page.waitForSelector('.tile');
  step('search filters the grid');
  await shot('catalog');

  await page.click('.tile');
  await page.waitForSelector('#view-item:not([hidden]) #f-title');
  const id = (await page.evaluate(() => location.hash)).match(/item\/(\d+)/)[1];
  step('item page opens for item ' + id);
  const newTitle = 'Jupe droite "Été", bleu marine';
  await page.fill('#f-title', newTitle);
  await page.fill('#f-price', '59.90');
  await page.fill('#f-tags', 'linen, summer');
  await page.click('#f-save');
  await waitFor(async () => (await page.textContent('#item-title')) === newTitle, 10000, 'the saved title');
  const item = await (await fetch(`${base}/api/items/${id}`)).json();
  if (item.title !== newTitle || item.price_cents !== 5990) throw new Error('the API has ' + JSON.stringify([item.title, item.price_cents]));
  step('title and price edited through the form and stored');
  // Panels and size guide: the pattern SVG of the item draws, and a graded item lists its sizes.
  const svgDrawn = () => page.evaluate(() => {
    const i = document.querySelector('#panels img');
    return !!i && i.complete && i.naturalWidth > 0;
  });
  if (!stub) {
    await waitFor(svgDrawn, 10000, 'the pattern SVG to draw');
    const sizes = await page.$$eval('#size-select option', (os) => os.map((o) => o.value));
    const guideRows = await page.$$eval('#sizeguide table.guide tbody tr', (rs) => rs.length);
    if (sizes.length < 3 || guideRows !== sizes.length - 1) throw new Error(`sizes ${sizes} but ${guideRows} size guide rows`);
    await page.selectOption('#size-select', sizes[sizes.length - 1]);
    await waitFor(async () => (await page.getAttribute('#panels img', 'src') || '').endsWith('size=' + sizes[sizes.length - 1]), 5000, 'the size switch');
    await waitFor(svgDrawn, 10000, 'the pattern SVG of size ' + sizes[sizes.length - 1]);
    await page.selectOption('#size-select', sizes[0]);
    step(`pattern panels drawn for sizes ${sizes.join(', ')}; size guide has ${guideRows} rows`);
  }

  // The review gate: an item waiting for review says so and stays out of the shop files.
  const itemStatus = (await (await fetch(`${base}/api/items/${id}`)).json()).status;
  if (itemStatus !== 'needs_review') {
    // This capture was confident enough to be approved at once: put it back to review so that the
    // gate is exercised all the same.
    await fetch(`${base}/api/items/${id}`, { method: 'PATCH', headers: { 'Content-Type': 'application/json' }, body: '{"status": "needs_review"}' });
    await page.evaluate(() => window.dispatchEvent(new HashChangeEvent('hashchange')));
  }
  await waitFor(async () => (await page.textContent('#item-status')) === 'Needs review', 10000, 'the "Needs review" badge');
  if (!(await page.isVisible('#item-review'))) throw new Error('the item page does not say that the item waits for review');
  if (!(await page.isVisible('#f-approve'))) throw new Error('no Approve button on an item waiting for review');
  step(`item ${itemStatus === 'needs_review' ? 'captured as' : 'set back to'} "Needs review": badge, notice and Approve button shown`);
  await shot('item-review');

  const downloadCsv = async (selector, name) => {
    const [download] = await Promise.all([page.waitForEvent('download', { timeout: 30000 }), page.click(selector)]);
    const path = join(work, name);
    await download.saveAs(path);
    return parse(readFileSync(path, 'utf8'), { columns: true });
  };
  await page.click('a[data-tab="export"]');
  await page.waitForSelector('#view-export:not([hidden])');
  await waitFor(async () => /^0 approved items .*1 waiting for review/.test(await page.textContent('#export-count')), 5000, 'the export count before approval');
  if ((await downloadCsv('#x-shopify', 'shopify-before.csv')).length) throw new Error('the Shopify CSV exports an item waiting for review');
  step('export page says the item waiting for review is left out, and the Shopify CSV holds no product');

  await page.evaluate((h) => { location.hash = h; }, '#/item/' + id);
  await page.waitForSelector('#view-item:not([hidden]) #f-approve');
  await page.click('#f-approve');
  await waitFor(async () => (await page.textContent('#item-status')) === 'Approved', 10000, 'approval');
  if (await page.isVisible('#item-review')) throw new Error('the review notice stays after approval');
  step('item approved');
  await page.waitForTimeout(800);
  await shot('item');
  if (!stub) {
    // Scroll the pattern and size guide cards just under the sticky header bar.
    await page.evaluate(() => {
      const top = document.querySelector('#panels').closest('.item-grid').getBoundingClientRect().top;
      window.scrollBy(0, top - document.querySelector('header.bar').offsetHeight - 12);
    });
    await waitFor(svgDrawn, 10000, 'the pattern SVG to draw');
    await page.waitForTimeout(300);
    await shot('item-pattern');
  }

  await page.click('a[data-tab="export"]');
  await page.waitForSelector('#view-export:not([hidden])');
  await waitFor(async () => /^1 approved item will be exported\.$/.test(await page.textContent('#export-count')), 5000, 'the export count');
  await shot('export');
  const rows = await downloadCsv('#x-shopify', 'shopify.csv');
  const product = rows.find((r) => r.Title);
  if (!product || product.Title !== newTitle) throw new Error('the Shopify CSV holds title ' + (product && product.Title));
  if (!rows.every((r) => r['URL handle'] === 'brw-001')) throw new Error('unexpected handles ' + rows.map((r) => r['URL handle']));
  const variants = rows.filter((r) => r['Option1 value']).map((r) => r['Option1 value']);
  if (!stub) {
    const graded = ((await (await fetch(`${base}/api/items/${id}/sizeguide.json`)).json()).sizes || []);
    if (variants.join() !== graded.join()) throw new Error(`Shopify variants ${variants} but graded sizes ${graded}`);
  }
  step(`Shopify CSV downloaded (${rows.length} rows, variants ${variants.join(', ')}) and its title reads back exactly`);

  if (!stub) {
  const zipRes = await fetch(`${base}/api/export/catalog.zip`);
  const zip = Buffer.from(await zipRes.arrayBuffer());
  if (!zipRes.ok || zip.readUInt32LE(0) !== 0x04034b50) throw new Error('catalog.zip: HTTP ' + zipRes.status + ' ' + zip.subarray(0, 200));
  step(`catalog.zip served (${zip.length} bytes)`);
  }

  if (pageErrors.length) throw new Error('JavaScript errors on the page: ' + pageErrors.join('; '));
  step('no JavaScript errors');
}

let code = 0;
try {
  await main();
} catch (e) {
  code = 1;
  console.log('FAIL ' + e.message);
  console.log('--- garmcapd log (tail) ---\n' + daemonLog.split('\n').slice(-40).join('\n'));
} finally {
  if (context) await context.close().catch(() => {});
  if (daemon && daemon.exitCode === null) {
    daemon.kill('SIGTERM');
    await waitFor(async () => daemon.exitCode !== null || daemon.signalCode !== null, 15000, 'garmcapd to stop').catch(() => daemon.kill('SIGKILL'));
  }
  rmSync(work, { recursive: true, force: true });
}
console.log(`${passed} passed, ${code ? 1 : 0} failed`);
process.exit(code);
