// Browser test of the web UI: Debian's chromium driven by playwright-core against the real
// garmcapd on the simulated rig, on a free loopback port, with a fresh catalog and profile.
//   node browser_test.mjs GARMCAPD WEB_DIR [SCREENSHOT_DIR] [--rig CASE_DIR]
//   node browser_test.mjs --stub WEB_DIR [SCREENSHOT_DIR]   (UI only, against stub_server.mjs)
// --rig: a rig case folder (empty.png or .jpg, dressed.png or .jpg, truth.json, e.g.
// tests/data/rig/case_002)
// that garmcapd replays (--camera replay), so every run sees the same garment; without it the
// daemon's synthetic camera renders random scenes.
// Steps, on a portrait tablet (768x1024): calibrate (bare form), capture a garment with a double
// tap (one job), see the result with Approve in view, a failed capture in red with what to do and
// the SKU kept, the catalog, the item page: edit the title and price, correct a measurement (the
// measured value kept in result.json), the review gate of the export, approve, export the Shopify
// CSV and read it back. Then on a 1024x1366 tablet: capture again, Approve in view, approve from
// the catalog with the bulk action. At 768x1024, 1024x1366 and 1366x1024 the live preview's frame
// must fill its box (at most 10 % black bars).
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
    viewport: { width: 768, height: 1024 },
    acceptDownloads: true,
  });
  const page = context.pages()[0] || await context.newPage();
  const pageErrors = [];
  page.on('pageerror', (e) => pageErrors.push(e.message));
  const shot = async (name) => {
    if (!shotDir) return;
    // A toast is transient: keep it out of the documentation screenshots.
    await page.evaluate(() => { document.querySelector('#toast').hidden = true; });
    const vp = page.viewportSize();
    await page.screenshot({ path: join(shotDir, `${name}-${vp.width}x${vp.height}.png`) });
  };
  // "In view": the whole element inside the viewport, as the page stands (no scrolling by the test).
  const inView = (sel) => page.evaluate((q) => {
    const r = document.querySelector(q).getBoundingClientRect();
    return r.width > 0 && r.top >= 0 && r.bottom <= window.innerHeight && r.left >= 0 && r.right <= window.innerWidth;
  }, sel);
  // The live preview's black bars: the share of the preview box (the dark card) that the camera
  // frame, drawn with object-fit: contain, leaves uncovered. A portrait camera in the old fixed
  // 4:3 box left 44 % of it black.
  const checkPreviewFills = async (what) => {
    await waitFor(() => page.evaluate(() => document.querySelector('#preview').naturalWidth > 0), 15000, 'the live preview to show a frame');
    await page.waitForTimeout(300);
    const m = await page.evaluate(() => {
      const box = document.querySelector('.preview'), img = document.querySelector('#preview');
      const nw = img.naturalWidth, nh = img.naturalHeight;
      const s = Math.min(img.clientWidth / nw, img.clientHeight / nh);
      return { bars: 1 - (nw * s * nh * s) / (box.clientWidth * box.clientHeight), frame: `${nw}x${nh}`, box: `${box.clientWidth}x${box.clientHeight}` };
    });
    const vp = page.viewportSize();
    if (!(m.bars <= 0.10)) throw new Error(`${what}: the ${m.frame} preview frame leaves ${(100 * m.bars).toFixed(1)} % of its ${m.box} box black at ${vp.width}x${vp.height} (at most 10 %)`);
    step(`${what}: the ${m.frame} preview frame fills its ${m.box} box at ${vp.width}x${vp.height} (${(100 * m.bars).toFixed(1)} % bars)`);
  };
  const captureAndSeeResult = async (sku, what) => {
    await page.fill('#sku', sku);
    await page.dblclick('#btn-capture');  // a double tap must make one job
    await page.waitForSelector('#job:not([hidden])');
    await waitFor(async () => {
      const failed = await page.$('#job.failed');
      if (failed) throw new Error('the capture job failed: ' + await page.textContent('#job-error'));
      return await page.isVisible('#last') && (await page.textContent('#last-sku')).includes(sku);
    }, JOB_TIMEOUT_MS, 'the capture to finish');
    await page.waitForTimeout(500);
    // An item confident enough is approved at once and has no Approve button; then the way to
    // check and correct it must be in view.
    const action = (await page.isVisible('#last-approve')) ? '#last-approve' : '#last-open';
    if (!(await inView(action)) || !(await inView('#last-type')))
      throw new Error(`${what}: the result and Approve are not in view (scrollY ${await page.evaluate(() => window.scrollY)})`);
    const scrolled = await page.evaluate(() => window.scrollY);
    if (scrolled !== 0) throw new Error(`${what}: the page had to scroll ${scrolled} px to show the result`);
    step(`${what}: result "${(await page.textContent('#last-type')).trim()}" and ${action === '#last-approve' ? 'Approve' : '"Check & correct" (approved at once)'} in view at ${page.viewportSize().width}x${page.viewportSize().height} (page scrolled by ${scrolled} px)`);
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
  await checkPreviewFills('live preview');

  await page.click('#btn-empty');
  await waitFor(async () => !(await page.isDisabled('#btn-capture')), JOB_TIMEOUT_MS, 'calibration (bare-form job)');
  step('bare-form capture calibrates the station');

  await captureAndSeeResult('BRW-001', 'capture (double tap)');
  await shot('capture-result');
  // The result lists what staff must check apart from notes on how it was read (the item's
  // `checks`, daemon/src/review_policy.cpp): a note is never shown as a check, nor the reverse.
  {
    const checks = await page.$$eval('#last-warn li', (l) => l.map((e) => e.textContent));
    const notes = await page.$$eval('#last-notes li', (l) => l.map((e) => e.textContent));
    if (notes.some((t) => !t.startsWith('Note: ')) || checks.some((t) => !t.startsWith('Check')))
      throw new Error('checks and notes mixed up: ' + JSON.stringify({ checks, notes }));
    if (stub && (checks.length !== 1 || !checks[0].includes('centre front') || notes.length !== 1 ||
                 !notes[0].includes('recipe'))) {
      throw new Error('the stub item\'s check and draft note are not listed apart: ' +
                      JSON.stringify({ checks, notes }));
    }
    step(`the result lists ${checks.length} check(s) to act on and ${notes.length} note(s) apart`);
  }

  // A failed capture: red, a toast, plain words and the next step, and the SKU stays. Against the
  // stub only: the simulated rig has no fault that fails a capture once the form is calibrated
  // (a slow or pulled camera still delivers the replayed frame).
  if (stub) {
    const failSku = 'FAIL-7';
    await page.fill('#sku', failSku);
    await page.click('#btn-capture');
    await waitFor(async () => page.isVisible('#job.failed'), 60000, 'the capture to fail');
    const failure = { what: await page.textContent('#job-error-what'), next: await page.textContent('#job-error-next'),
      toastBad: await page.evaluate(() => { const t = document.querySelector('#toast'); return !t.hidden && t.classList.contains('bad'); }),
      sku: await page.inputValue('#sku'),
      color: await page.evaluate(() => getComputedStyle(document.querySelector('#job')).borderColor) };
    if (!failure.what || !/^What to do: /.test(failure.next) || !failure.toastBad || failure.sku !== failSku || !/rgb\(198, 40, 40\)/.test(failure.color))
      throw new Error('a failed capture shows ' + JSON.stringify(failure));
    if (!(await inView('#job-error-next'))) throw new Error('the failure and the next step are not in view');
    step(`failed capture: red, toast, "${failure.what}" ${failure.next}; SKU ${failure.sku} kept`);
    await shot('capture-failed');
    await page.fill('#sku', '');
  }

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
  // Correct a measurement: the corrected value is the item's, the measured one stays in result.json.
  await page.waitForSelector('#f-meas input');
  const measName = await page.getAttribute('#f-meas input', 'data-name');
  const measured = (await (await fetch(`${base}/api/items/${id}/result.json`)).json()).measurements[measName];
  const corrected = Math.round((measured + 1.5) * 10) / 10;
  await page.fill(`#f-meas input[data-name="${measName}"]`, String(corrected));
  await page.click('#f-save');
  await waitFor(async () => (await (await fetch(`${base}/api/items/${id}`)).json()).measurements[measName] === corrected, 10000, 'the corrected measurement');
  const after = (await (await fetch(`${base}/api/items/${id}/result.json`)).json()).measurements[measName];
  if (Math.abs(after - measured) > 1e-9) throw new Error(`result.json's ${measName} changed from ${measured} to ${after}`);
  await page.waitForSelector(`.meas-row.changed input[data-name="${measName}"]`);
  step(`${measName} corrected to ${corrected} cm; the measured ${measured} cm is kept for the record`);
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
    // The tape measure: a taped value is stored with the station's reading, and the corrections
    // panel lists the item's type and measurement, waiting for two more garments.
    await page.waitForSelector('#tape-meas input');
    const tapeName = await page.getAttribute('#tape-meas input', 'data-name');
    await page.fill(`#tape-meas input[data-name="${tapeName}"]`, '88.5');
    await page.click('#tape-save');
    await waitFor(async () => ((await (await fetch(`${base}/api/tape`)).json()).tape || []).some((r) => String(r.item) === id && r.measurement === tapeName && r.tape_cm === 88.5), 10000, 'the taped measurement');
    await waitFor(async () => /none yet \(2 more\)/.test(await page.textContent('#corrections')), 10000, 'the corrections panel');
    await page.evaluate(() => document.querySelector('#tape-form').scrollIntoView());
    await shot('item-tape');
    step(`${tapeName} taped at 88.5 cm; the corrections panel waits for 2 more garments`);
  } else {
    // A busy station (503 + Retry-After while another marker is laid): the download says so,
    // waits and arrives.
    const marker = page.locator('#pattern-links a', { hasText: 'Marker 150 cm PDF' });
    const [download] = await Promise.all([page.waitForEvent('download', { timeout: 15000 }),
      (async () => {
        await marker.click();
        await waitFor(async () => /busy with another marker; trying again in 1 s/.test(await page.textContent('#toast') || ''), 5000, 'the busy notice');
      })()]);
    if (download.suggestedFilename() !== 'stub_marker.pdf') throw new Error('the marker downloaded as ' + download.suggestedFilename());
    step('marker download waited out a busy station (503, Retry-After: 1) and arrived');
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
  // Links to this station are refused by the export: the setup asks for the shop's public
  // addresses once, and a bad one is refused with the field named.
  await waitFor(async () => await page.isVisible('#s-missing'), 5000, 'the "set up your shop" notice');
  await page.fill('#s-public_base_url', 'ftp://shop.example/files');
  await page.click('#s-save');
  await waitFor(async () => /Not saved: public_base_url/.test(await page.textContent('#toast') || ''), 5000, 'the refusal of an ftp:// URL');
  await page.fill('#s-public_base_url', 'https://shop.example/files');
  await page.fill('#s-store_url', 'https://shop.example');
  await page.fill('#s-brand', 'Atelier Browser');
  await page.click('#s-save');
  await waitFor(async () => /Shop settings saved/.test(await page.textContent('#toast') || ''), 5000, 'the saved shop settings');
  if (await page.isVisible('#s-missing')) throw new Error('the "set up your shop" notice stays after saving');
  step('shop set up on the export page: an ftp:// image URL refused naming the field, then saved');
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
    const piece = (await (await fetch(`${base}/api/items/${id}/sizeguide.json`)).json()).base_size;
    if (variants.join() !== piece) throw new Error(`Shopify variants ${variants} but the piece is size ${piece}`);
  }
  step(`Shopify CSV downloaded (${rows.length} rows, variants ${variants.join(', ')}) and its title reads back exactly`);

  if (!stub) {
  const zipRes = await fetch(`${base}/api/export/catalog.zip?base_url=https://shop.example/files&store_url=https://shop.example&brand=Atelier`);
  const zip = Buffer.from(await zipRes.arrayBuffer());
  if (!zipRes.ok || zip.readUInt32LE(0) !== 0x04034b50) throw new Error('catalog.zip: HTTP ' + zipRes.status + ' ' + zip.subarray(0, 200));
  step(`catalog.zip served (${zip.length} bytes)`);
  }

  // The taller tablet, portrait 1024x1366: capture again; then approve from the catalog at once.
  // The preview fills its box here and in landscape (no side bars) before and after a capture.
  await page.setViewportSize({ width: 1024, height: 1366 });
  await page.evaluate(() => { location.hash = '#/capture'; });
  await page.waitForSelector('#view-capture:not([hidden])');
  await checkPreviewFills('live preview');
  await page.setViewportSize({ width: 1366, height: 1024 });
  await checkPreviewFills('live preview, landscape');
  await page.setViewportSize({ width: 1024, height: 1366 });
  await captureAndSeeResult('BRW-002', 'second capture');
  await checkPreviewFills('live preview beside the result');
  await shot('capture-result');
  await page.click('a[data-tab="catalog"]');
  await page.waitForSelector('.tile');
  const second = (await (await fetch(`${base}/api/items?q=BRW-002`)).json()).items[0];
  if (second.status !== 'approved') {
    await page.check(`.pick input[data-id="${second.id}"]`);
    await page.waitForSelector('#bulk-approve:not([hidden])');
    await shot('catalog-select');
    await page.click('#bulk-approve');
    await waitFor(async () => (await (await fetch(`${base}/api/items/${second.id}`)).json()).status === 'approved', 10000, 'the bulk approval');
    step('approved from the catalog with "Approve selected"');
  }
  await page.evaluate((h) => { location.hash = h; }, '#/item/' + second.id);
  await page.waitForSelector('#view-item:not([hidden]) #f-meas input');
  await page.waitForTimeout(500);
  await shot('item');

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
