// Browser test of the hub's review UI: Debian's chromium driven by playwright-core against the
// real `garmcap-hub` on a real PostgreSQL (initdb and pg_ctl in a temporary folder on a free
// loopback port, as nobody when run as root: tests/hub/temp_postgres.h does the same in C++).
// Two stations push items through the hub's push API with their own tokens (blobs first, real
// JPEG frames of the rig); then, in a portrait 768x1024 tablet viewport:
//  - the admin's token, asked once, becomes an HttpOnly cookie; the catalog lists the items of
//    both stations with their thumbnails (loaded from the hub's blobs through the cookie);
//  - the station filter, filled from /api/hub/stations, narrows the list to one station, the
//    status filter to one status;
//  - an item page shows photos, measurements, the size guide and the station; Approve changes
//    the item's status at the hub (read back over the API with the admin's bearer token), and
//    "Approve selected" approves several;
//  - the export page downloads the chain's Shopify CSV and catalog.zip through the cookie: one
//    product per approved item of the station chosen (as many as the API lists), every station's
//    for "All stations"; a station's token exports its own station's items only;
//  - a station's token reads only its own station's items and sees no review control.
//   node browser_hub_test.mjs GARMCAP_HUB WEB_DIR SCREENSHOT_DIR TEST_DATA_DIR
// Exits 77 (skipped) without PostgreSQL's binaries. Prints one line per step and "N passed".
import { spawn, spawnSync } from 'node:child_process';
import { createHash } from 'node:crypto';
import { chownSync, existsSync, mkdirSync, mkdtempSync, readdirSync, readFileSync, rmSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join } from 'node:path';
import { chromium } from 'playwright-core';
import { parse } from 'csv-parse/sync';

const [hubBin, webDir, shotDir, dataDir] = process.argv.slice(2);
if (!hubBin || !webDir || !shotDir || !dataDir) {
  console.error('usage: node browser_hub_test.mjs GARMCAP_HUB WEB_DIR SCREENSHOT_DIR TEST_DATA_DIR');
  process.exit(2);
}
const CHROMIUM = process.env.GARMCAP_CHROMIUM || '/usr/bin/chromium';
const ADMIN = 'chain-admin-token-0123456789';
const TOKENS = { shop1: 'shop1-token-0123456789abcdef', shop2: 'shop2-token-0123456789abcdef' };
const sha256 = (b) => createHash('sha256').update(b).digest('hex');

const pgRoot = '/usr/lib/postgresql';
const pgBin = existsSync(pgRoot) ? readdirSync(pgRoot).sort().reverse().map((v) => join(pgRoot, v, 'bin'))
  .find((d) => existsSync(join(d, 'initdb'))) : undefined;
if (!pgBin) {
  console.log('SKIP: no PostgreSQL binaries under /usr/lib/postgresql (./station.sh installs them)');
  process.exit(77);
}

let passed = 0;
const step = (name) => { passed++; console.log('ok   ' + name); };
function check(cond, what) { if (!cond) throw new Error(what); }

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
    await new Promise((r) => setTimeout(r, 200));
  }
  throw new Error('timed out waiting for ' + what + (last ? ': ' + last.message : ''));
}

// PostgreSQL refuses to run as root: as root, its files and processes are nobody's.
const root = process.getuid() === 0;
function pg(args) {
  const r = root ? spawnSync('runuser', ['-u', 'nobody', '--', ...args], { encoding: 'utf8' })
    : spawnSync(args[0], args.slice(1), { encoding: 'utf8' });
  if (r.status !== 0) throw new Error(args.join(' ') + ' failed: ' + r.stderr + r.stdout);
}

const work = mkdtempSync(join(tmpdir(), 'garmcap-hubui-'));
if (root) chownSync(work, 65534, 65534);
const pgData = join(work, 'pg');
const pgPort = await freePort();
const hubPort = await freePort();
const base = `http://127.0.0.1:${hubPort}`;
let hub = null, browser = null, hubLog = '', pgStarted = false;

async function cleanup() {
  if (browser) await browser.close().catch(() => {});
  if (hub && hub.exitCode === null) {
    const exited = new Promise((r) => hub.once('exit', r));
    hub.kill('SIGTERM');
    await exited;
  }
  if (pgStarted) { try { pg([join(pgBin, 'pg_ctl'), '-D', pgData, '-m', 'immediate', 'stop']); } catch (e) { /* gone */ } }
  rmSync(work, { recursive: true, force: true });
}

// The API as a station or the admin would call it.
async function call(method, path, token, body, type = 'application/json') {
  const headers = { Authorization: 'Bearer ' + token };
  if (body !== undefined) headers['Content-Type'] = type;
  const res = await fetch(base + path, { method, headers, body: body === undefined ? undefined : (type === 'application/json' ? JSON.stringify(body) : body) });
  const text = await res.text();
  if (!res.ok) throw new Error(method + ' ' + path + ': ' + res.status + ' ' + text);
  return text ? JSON.parse(text) : null;
}

// The items each station sends: a real rig frame each (distinct blobs, rig_physical's cases in
// order, titled for what they show), measurements, a size guide.
const photos = readdirSync(join(dataDir, 'rig_physical')).filter((d) => existsSync(join(dataDir, 'rig_physical', d, 'dressed.jpg')))
  .sort().map((d) => readFileSync(join(dataDir, 'rig_physical', d, 'dressed.jpg')));
const ITEMS = [
  { station: 'shop1', local: 1, sku: 'S1-0001', title: 'White three-quarter sleeve top', type: 'top', price: 3900 },
  { station: 'shop1', local: 2, sku: 'S1-0002', title: 'Cream sleeveless dress', type: 'dress', price: 2500 },
  { station: 'shop1', local: 3, sku: 'S1-0003', title: 'Purple cropped trousers', type: 'pants', price: null },
  { station: 'shop2', local: 1, sku: 'S2-0001', title: 'Purple midi skirt', type: 'skirt', price: 4500 },
  { station: 'shop2', local: 2, sku: 'S2-0002', title: 'White short-sleeve top', type: 'top', price: 3200 },
];

const BUST_NOTE = 'bust_circ: sleeves cover the sides at the bust; read from the sides down to 6 cm lower, where they show';
function stationItem(it, sha) {
  const meas = { waist_circ: 70 + it.local, hip_circ: 96 + it.local, garment_length: 60 + 2 * it.local };
  return {
    id: it.local, sku: it.sku, title: it.title, type: it.type, status: 'needs_review', price_cents: it.price,
    measurements: meas, base_size: '38',
    // A station of today says which warnings are checks (local 1); an older one did not (local 2).
    ...(it.local === 1 ? { warnings: [BUST_NOTE, 'waist line uncertain'], checks: ['waist line uncertain'] }
      : { warnings: it.local === 2 ? ['waist line uncertain'] : [] }),
    images: { product: { sha256: sha, media_type: 'image/jpeg' } },
    size_guide: {
      units: 'cm', type: it.type, chart: 'eu_women', base_size: '38', measurements: Object.keys(meas),
      rows: ['36', '38', '40'].map((s, k) => ({ size: s, garment: Object.fromEntries(Object.entries(meas).map(([n, v]) => [n, v + (k - 1) * 4])), body: {} })),
    },
  };
}

let failed = false;
try {
  check(photos.length >= ITEMS.length, 'need ' + ITEMS.length + ' rig photos in ' + dataDir);
  pg([join(pgBin, 'initdb'), '-D', pgData, '-U', 'garmcap', '--auth=trust', '-E', 'UTF8', '--no-locale', '--no-sync']);
  pg([join(pgBin, 'pg_ctl'), '-D', pgData, '-l', join(work, 'pg.log'), '-o',
    `-p ${pgPort} -k ${work} -c listen_addresses=127.0.0.1`, '-w', 'start']);
  pgStarted = true;
  pg([join(pgBin, 'createdb'), '-h', '127.0.0.1', '-p', String(pgPort), '-U', 'garmcap', 'hub']);

  hub = spawn(hubBin, ['--db', `host=127.0.0.1 port=${pgPort} user=garmcap dbname=hub`,
    '--listen', `127.0.0.1:${hubPort}`, '--web-dir', webDir, '--admin-token-sha256', sha256(ADMIN),
    '--station', 'shop1=' + sha256(TOKENS.shop1), '--station', 'shop2=' + sha256(TOKENS.shop2)],
  { stdio: ['ignore', 'pipe', 'pipe'] });
  hub.stdout.on('data', (d) => { hubLog += d; });
  hub.stderr.on('data', (d) => { hubLog += d; });
  await waitFor(async () => (await fetch(base + '/api/hub/health')).ok, 30000, 'garmcap-hub to answer');
  step('a real PostgreSQL and garmcap-hub on loopback');

  const hubIds = {};
  for (const [k, it] of ITEMS.entries()) {
    const sha = sha256(photos[k]);
    await call('PUT', '/api/hub/blobs/' + sha, TOKENS[it.station], photos[k], 'application/octet-stream');
    const r = await call('POST', '/api/hub/push', TOKENS[it.station], { local_id: it.local, item: stationItem(it, sha), deleted: false });
    hubIds[it.sku] = r.id;
  }
  step('two stations pushed ' + ITEMS.length + ' items with their photos');

  browser = await chromium.launch({ executablePath: CHROMIUM, args: ['--no-sandbox'] });
  const context = await browser.newContext({ viewport: { width: 768, height: 1024 }, deviceScaleFactor: 1, hasTouch: true });
  const page = await context.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  let prompts = 0;
  page.on('dialog', (d) => { prompts++; d.type() === 'prompt' ? d.accept(ADMIN) : d.dismiss(); });
  await page.goto(base + '/');

  // The token once, then the catalog of both stations with their photos.
  await page.waitForFunction((n) => document.querySelectorAll('#grid .tile').length === n, ITEMS.length, { timeout: 20000 });
  const stations = await page.$$eval('#grid .tile', (ts) => ts.map((t) => t.dataset.station));
  check(stations.includes('shop1') && stations.includes('shop2'), 'stations listed: ' + stations);
  check(prompts === 1, 'the token was asked ' + prompts + ' times');
  const cookies = await context.cookies();
  const sessionCookie = cookies.find((c) => c.name === 'garmcap_session');
  check(sessionCookie && sessionCookie.httpOnly && sessionCookie.sameSite === 'Strict', 'HttpOnly SameSite=Strict cookie: ' + JSON.stringify(cookies));
  check(await page.evaluate(() => document.cookie) === '', 'the page cannot read the session cookie');
  step('the admin token, asked once, became an HttpOnly cookie; the list holds both stations\' items: ' + stations.join(','));
  await page.waitForFunction(() => Array.from(document.querySelectorAll('#grid .tile img')).every((i) => i.complete && i.naturalWidth > 0), null, { timeout: 20000 });
  const thumbs = await page.$$eval('#grid .tile img', (is) => is.length);
  check(thumbs === ITEMS.length, thumbs + ' thumbnails');
  const titles = await page.$$eval('#grid .tile .t', (ts) => ts.map((t) => t.textContent));
  check(titles[0] === 'White short-sleeve top', 'newest first: ' + titles);
  check(await page.$eval(`.tile[data-id="${hubIds['S1-0002']}"] .price`, (e) => e.textContent) === '25.00', 'price on the tile');
  step(thumbs + ' thumbnails decoded from the hub\'s blobs through the cookie; newest first; prices shown');
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  check(overflow <= 0, 'the catalog is ' + overflow + ' px wider than the 768 px screen');
  mkdirSync(shotDir, { recursive: true });
  await page.screenshot({ path: join(shotDir, 'hub-catalog-768x1024.png') });
  step('portrait 768x1024: no horizontal scrolling; screenshot hub-catalog-768x1024.png');

  // The station filter: filled from /api/hub/stations, it narrows the list to one station. It is
  // filled by a request of its own, beside the list's, so it is waited for, not assumed.
  await page.waitForFunction(() => document.querySelectorAll('#station-filter option').length > 1, null, { timeout: 10000 });
  const options = await page.$$eval('#station-filter option', (os) => os.map((o) => o.value + '=' + o.textContent));
  check(options.join('|') === '=All stations (5)|shop1=shop1 (3)|shop2=shop2 (2)', 'station options: ' + options.join('|'));
  await page.selectOption('#station-filter', 'shop2');
  await page.waitForFunction(() => {
    const ts = Array.from(document.querySelectorAll('#grid .tile'));
    return ts.length === 2 && ts.every((t) => t.dataset.station === 'shop2');
  }, null, { timeout: 10000 });
  step('station filter "shop2": only its 2 items');

  // Approve from the item page; read back over the API.
  const id = hubIds['S2-0001'];
  await page.click(`.tile[data-id="${id}"]`);
  await page.waitForFunction(() => document.querySelector('#item-title').textContent === 'Purple midi skirt', null, { timeout: 10000 });
  await page.waitForFunction(() => { const i = document.querySelector('#photos img'); return i && i.complete && i.naturalWidth > 0; }, null, { timeout: 10000 });
  check((await page.textContent('#item-station')) === 'from shop2', 'station of origin on the item page');
  const guideRows = await page.$$eval('#sizeguide table.guide tbody tr', (rs) => rs.map((r) => r.textContent));
  check(guideRows.length === 3 && guideRows[1].startsWith('38 (this piece)'), 'size guide rows: ' + guideRows);
  const meas = await page.$$eval('#item-meas tr', (rs) => rs.map((r) => r.textContent));
  check(meas.includes('Waist71.0 cm'), 'measurements: ' + meas);
  check(await page.isHidden('#f-reject'), 'no Reject while the station owns the item');
  const warns = await page.$$eval('#item-warn li', (ls) => ls.map((l) => l.textContent));
  check(JSON.stringify(warns) === JSON.stringify(['Note: ' + BUST_NOTE, 'Check: waist line uncertain']),
    'the station\'s check and note listed apart: ' + JSON.stringify(warns));
  step('item page: photo, measurements, size guide (3 sizes, this piece 38), station of origin');
  const itemOverflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  check(itemOverflow <= 0, 'the item page is ' + itemOverflow + ' px wider than the 768 px screen');
  await page.evaluate(() => window.scrollTo(0, 0));
  await page.screenshot({ path: join(shotDir, 'hub-item-768x1024.png') });
  await page.fill('#f-price', '47.50');
  await page.click('#f-approve');
  await page.waitForFunction(() => document.querySelector('#item-status').textContent === 'Approved', null, { timeout: 10000 });
  const approved = await call('GET', '/api/items/' + id, ADMIN);
  check(approved.status === 'approved' && approved.hub_owned === true && approved.price_cents === 4750,
    'at the hub: ' + JSON.stringify({ status: approved.status, hub_owned: approved.hub_owned, price: approved.price_cents }));
  step('Approve (with a new price) from the UI: the hub says approved, hub-owned, 47.50');

  // Hub-owned now: the title is editable here and Reject is offered.
  await page.fill('#f-title', 'Purple midi pencil skirt');
  await page.click('#f-save');
  await waitFor(async () => (await call('GET', '/api/items/' + id, ADMIN)).title === 'Purple midi pencil skirt', 10000, 'the title at the hub');
  check(await page.isVisible('#f-reject'), 'Reject offered once the hub owns the item');
  step('a hub-owned item: the title saved from the UI is the hub\'s');

  // The status filter, then several approved at once.
  // Back in the catalog the station filter is still shop2's; every station again.
  await page.click('#view-item a[href="#/catalog"]');
  await page.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 2, null, { timeout: 10000 });
  check(await page.inputValue('#station-filter') === 'shop2', 'the station filter kept');
  await page.selectOption('#station-filter', '');
  await page.waitForFunction((n) => document.querySelectorAll('#grid .tile').length === n, ITEMS.length, { timeout: 10000 });
  await page.selectOption('#status-filter', 'approved');
  await page.waitForFunction((i) => { const ts = document.querySelectorAll('#grid .tile'); return ts.length === 1 && ts[0].dataset.id === String(i); }, id, { timeout: 10000 });
  step('status filter "approved": only the approved item');
  await page.selectOption('#status-filter', 'needs_review');
  await page.selectOption('#station-filter', 'shop1');
  await page.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 3, null, { timeout: 10000 });
  for (const sku of ['S1-0001', 'S1-0003']) await page.check(`.pick input[data-id="${hubIds[sku]}"]`);
  check((await page.textContent('#bulk-approve')) === 'Approve selected (2)', 'bulk button');
  await page.click('#bulk-approve');
  await page.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 1, null, { timeout: 10000 });
  for (const sku of ['S1-0001', 'S1-0003']) check((await call('GET', '/api/items/' + hubIds[sku], ADMIN)).status === 'approved', sku + ' approved at the hub');
  check((await call('GET', '/api/items/' + hubIds['S1-0002'], ADMIN)).status === 'needs_review', 'the unpicked item untouched');
  step('"Approve selected" approved the 2 picked items of shop1 at the hub, not the third');

  // Search narrows too (the hub's trigram search).
  await page.selectOption('#status-filter', '');
  await page.selectOption('#station-filter', '');
  await page.fill('#search', 'top');
  await page.waitForFunction(() => {
    const ts = Array.from(document.querySelectorAll('#grid .tile'));
    return ts.length === 2 && ts.every((t) => /top/i.test(t.querySelector('.t').textContent)) &&
      new Set(ts.map((t) => t.dataset.station)).size === 2;
  }, null, { timeout: 10000 });
  step('search "top": the 2 tops, one of each station');

  // Keyset pages: 25 more items of shop2 make 30, a page is 24; "Show more" asks for the rest
  // after the last id shown, and every item is listed once.
  for (let local = 100; local < 125; local++) {
    await call('POST', '/api/hub/push', TOKENS.shop2, { local_id: local, item: { sku: 'S2-' + local, title: 'Plain tee ' + local,
      type: 'top', status: 'needs_review', price_cents: 1000 + local, measurements: {}, images: {} }, deleted: false });
  }
  await page.fill('#search', '');
  await page.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 24, null, { timeout: 10000 });
  check(await page.isVisible('#more'), '"Show more" under the first page');
  const pageAsks = [];
  page.on('request', (r) => { if (r.url().includes('/api/items?')) pageAsks.push(new URL(r.url()).searchParams.get('after')); });
  await page.click('#more');
  await page.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 30, null, { timeout: 10000 });
  const listed = await page.$$eval('#grid .tile', (ts) => ts.map((t) => Number(t.dataset.id)));
  check(new Set(listed).size === 30 && listed.every((v, k) => k === 0 || v < listed[k - 1]), 'ids once each, newest first: ' + listed);
  check(pageAsks.length === 1 && Number(pageAsks[0]) === listed[23], 'the second page asked after=' + pageAsks + ', the 24th id is ' + listed[23]);
  check(await page.isHidden('#more'), 'no "Show more" after the last page');
  check(await page.$$eval('#station-filter option', (os) => os[2].textContent) === 'shop2 (27)', 'the station counts follow');
  step('keyset pages: 24, then "Show more" after=' + pageAsks[0] + ' gives the other 6; 30 distinct items, newest first');

  // The export page: the chain's files through the session cookie (the page holds no token).
  // What the API lists as approved, per station, is what a shop file holds.
  const approvedSkus = async (station) => {
    const skus = [];
    for (let after = null; ;) {
      const r = await call('GET', '/api/items?limit=500&status=approved' + (station ? '&station=' + station : '') + (after ? '&after=' + after : ''), ADMIN);
      skus.push(...r.items.map((i) => i.sku));
      if (!r.next) return skus.sort();
      after = r.next;
    }
  };
  const downloadFrom = async (p, selector) => {
    const [dl] = await Promise.all([p.waitForEvent('download', { timeout: 30000 }), p.click(selector)]);
    const path = join(work, 'dl-' + passed + '-' + dl.suggestedFilename());
    await dl.saveAs(path);
    return { name: dl.suggestedFilename(), path };
  };
  // Shopify: a product's first row has its title; further rows are its other images or sizes.
  const productSkus = (path) => parse(readFileSync(path, 'utf8'), { columns: true }).filter((r) => r.Title).map((r) => r.SKU).sort();
  await page.click('.tabs a[data-tab="export"]');
  await page.waitForSelector('#view-export:not([hidden])');
  await page.waitForFunction(() => document.querySelectorAll('#x-station option').length === 3, null, { timeout: 10000 });
  check(await page.$eval('.tabs a[data-tab="export"]', (a) => a.classList.contains('on')), 'the Export tab is marked');
  await page.fill('#x-base_url', 'https://files.shop.test/chain');
  await page.fill('#x-store_url', 'https://shop.test');
  await page.selectOption('#x-station', 'shop1');
  const shop1 = await approvedSkus('shop1');
  check(shop1.length === 2, 'shop1 has ' + shop1.length + ' approved items at the hub');
  await page.waitForFunction((n) => document.querySelector('#x-count').dataset.approved === String(n), shop1.length, { timeout: 10000 });
  const countText = await page.textContent('#x-count');
  check(/^2 approved items of shop1 will be exported; 1 waiting for review is left out/.test(countText), 'count: ' + countText);
  const csv1 = await downloadFrom(page, '#x-shopify');
  check(csv1.name === 'shopify.csv', 'downloaded as ' + csv1.name);
  const rows1 = productSkus(csv1.path);
  check(JSON.stringify(rows1) === JSON.stringify(shop1), 'shop1\'s Shopify products ' + rows1 + ', the API lists ' + shop1);
  await page.selectOption('#x-station', '');
  const every = await approvedSkus('');
  await page.waitForFunction((n) => document.querySelector('#x-count').dataset.approved === String(n), every.length, { timeout: 10000 });
  const rowsAll = productSkus((await downloadFrom(page, '#x-shopify')).path);
  check(rowsAll.length === every.length && JSON.stringify(rowsAll) === JSON.stringify(every), 'every station\'s products ' + rowsAll + ', the API lists ' + every);
  await page.selectOption('#x-station', 'shop2');
  const zip = await downloadFrom(page, '#x-zip');
  const zipCheck = spawnSync('/usr/bin/python3', ['-c', `import csv, io, sys, zipfile
z = zipfile.ZipFile(sys.argv[1]); assert z.testzip() is None
name = [n for n in z.namelist() if n.endswith('shopify.csv')][0]
rows = list(csv.DictReader(io.StringIO(z.read(name).decode('utf-8'))))
print(' '.join(sorted(r['SKU'] for r in rows if r['Title'])))`, zip.path], { encoding: 'utf8' });
  check(zipCheck.status === 0, 'catalog.zip: ' + zipCheck.stderr);
  const shop2 = await approvedSkus('shop2');
  check(zip.name === 'catalog.zip' && zipCheck.stdout.trim() === shop2.join(' '), 'catalog.zip of shop2 holds ' + zipCheck.stdout.trim() + ', the API lists ' + shop2);
  check((await fetch(base + '/api/export/shopify.csv?base_url=https://files.shop.test/chain')).status === 401, 'an export without the cookie or a token is refused');
  step('export page: shop1\'s Shopify CSV (' + rows1.length + ' products), every station\'s (' + rowsAll.length + ') and shop2\'s catalog.zip downloaded through the cookie, each equal to the API\'s approved items');

  // A station's token reads only its own items, and reviews nothing.
  const ctx2 = await browser.newContext({ viewport: { width: 768, height: 1024 } });
  const p2 = await ctx2.newPage();
  p2.on('pageerror', (e) => errors.push(e.message));
  p2.on('dialog', (d) => d.accept(TOKENS.shop1));
  await p2.goto(base + '/');
  await p2.waitForFunction(() => document.querySelectorAll('#grid .tile').length === 3, null, { timeout: 20000 });
  const own = await p2.$$eval('#grid .tile', (ts) => ts.map((t) => t.dataset.station));
  check(own.every((s) => s === 'shop1'), 'a station token sees ' + own);
  await p2.waitForFunction(() => document.querySelectorAll('#station-filter option').length > 1, null, { timeout: 10000 });
  check((await p2.$$eval('#station-filter option', (os) => os.map((o) => o.value))).join(',') === ',shop1', 'its filter names only itself');
  check((await p2.textContent('#who-text')) === 'Station shop1', 'who');
  check(await p2.$$eval('.pick', (ps) => ps.every((p) => getComputedStyle(p).display === 'none')), 'no pick boxes for a station');
  step('a station token: its 3 items only, no review controls');
  await p2.click('.tabs a[data-tab="export"]');
  await p2.waitForFunction(() => document.querySelector('#x-count').dataset.approved !== undefined, null, { timeout: 10000 });
  check((await p2.$$eval('#x-station option', (os) => os.map((o) => o.value))).join(',') === 'shop1', 'a station exports only itself');
  await p2.fill('#x-base_url', 'https://files.shop.test/chain');
  const own1 = productSkus((await downloadFrom(p2, '#x-shopify')).path);
  check(JSON.stringify(own1) === JSON.stringify(shop1), 'a station\'s export: ' + own1 + ', its approved items: ' + shop1);
  step('a station token\'s export page: its own station only, its ' + own1.length + ' approved items');

  // Logged out, the cookie is gone and the API refuses the browser.
  const out = await p2.evaluate(async () => { await fetch('/api/session', { method: 'DELETE' }); return (await fetch('/api/items')).status; });
  check(out === 401, 'after DELETE /api/session: ' + out);
  step('DELETE /api/session logs the browser out (401 after)');

  check(errors.length === 0, 'JavaScript errors: ' + errors.join('; '));
  step('no JavaScript errors');
} catch (e) {
  failed = true;
  console.log('FAIL ' + e.message);
  console.log('--- hub log ---\n' + hubLog.slice(-3000));
}
await cleanup();
console.log(passed + ' passed, ' + (failed ? 1 : 0) + ' failed');
process.exit(failed ? 1 : 0);
