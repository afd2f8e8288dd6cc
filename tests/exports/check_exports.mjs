// Consumer checks: the exports written by write_export_samples are read back by independent
// parsers from npm (dxf-parser for DXF, csv-parse for CSV/TSV) and compared with truth.json.
//   node check_exports.mjs DIR
// Prints one line per check and a closing "N passed, N failed"; exits 1 on any failure.
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import DxfParser from 'dxf-parser';
import { parse } from 'csv-parse/sync';

const dir = process.argv[2];
if (!dir) { console.error('usage: node check_exports.mjs DIR'); process.exit(2); }
const truth = JSON.parse(readFileSync(join(dir, 'truth.json'), 'utf8'));
let passed = 0, failed = 0;
function check(name, ok, detail = '') {
  if (ok) { passed++; console.log('ok   ' + name); } else { failed++; console.log('FAIL ' + name + (detail ? ': ' + detail : '')); }
}
const TOL_MM = 0.1;
const fix1 = (v) => (Math.round(v * 10) / 10).toFixed(1);  // half away from zero, as exported
const dist = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

// ---- DXF ------------------------------------------------------------------------------------
function readDxf(file) {
  return new DxfParser().parseSync(readFileSync(join(dir, file), 'utf8'));
}
function checkPieces(dxf, expected, label) {
  const inserted = new Set((dxf.entities || []).filter((e) => e.type === 'INSERT').map((e) => e.name));
  for (const [blockName, want] of Object.entries(expected)) {
    const block = dxf.blocks[blockName];
    check(`${label}: block ${blockName} exists`, !!block);
    if (!block) continue;
    check(`${label}: block ${blockName} is inserted`, inserted.has(blockName));
    const ents = block.entities || [];
    // Layer 1 is the cut line (seam allowance included), layer 14 the sew line: the piece.
    const poly = (layer) => ents.filter((e) => e.layer === layer && (e.type === 'POLYLINE' || e.type === 'LWPOLYLINE'));
    const cut = poly('1');
    check(`${label}: ${blockName} has one closed layer-1 cut line`, cut.length === 1 && cut[0].shape === true, `found ${cut.length}`);
    const boundary = poly('14');
    check(`${label}: ${blockName} has one layer-14 sew line`, boundary.length === 1, `found ${boundary.length}`);
    if (boundary.length !== 1) continue;
    const b = boundary[0];
    check(`${label}: ${blockName} sew line closed`, b.shape === true);
    const got = b.vertices.map((v) => [v.x, v.y]);
    check(`${label}: ${blockName} vertex count`, got.length === want.outline.length, `${got.length} vs ${want.outline.length}`);
    let maxErr = 0;
    for (let i = 0; i < Math.min(got.length, want.outline.length); i++) maxErr = Math.max(maxErr, dist(got[i], want.outline[i]));
    check(`${label}: ${blockName} outline within ${TOL_MM} mm (max ${maxErr.toFixed(4)} mm)`, maxErr <= TOL_MM);
    const texts = ents.filter((e) => e.type === 'TEXT').map((e) => e.text);
    for (const t of [`Piece Name: ${want.piece}`, `Size: ${want.size}`, `Quantity: ${want.quantity}`])
      check(`${label}: ${blockName} text "${t}"`, texts.includes(t));
    const grain = ents.filter((e) => e.layer === '7' && e.type === 'LINE');
    check(`${label}: ${blockName} grainline on layer 7`, grain.length === 1 &&
      dist([grain[0].vertices[0].x, grain[0].vertices[0].y], want.grainline[0]) <= TOL_MM &&
      dist([grain[0].vertices[1].x, grain[0].vertices[1].y], want.grainline[1]) <= TOL_MM);
    // A notch is a 5 mm slit cut from the cut line inward, on the line through the sew line's
    // notch (its normal there).
    const cutRing = cut.length === 1 ? cut[0].vertices.map((v) => [v.x, v.y]) : [];
    const segDist = (p, a, b) => {
      const d = [b[0] - a[0], b[1] - a[1]], l2 = d[0] * d[0] + d[1] * d[1];
      const t = l2 ? Math.max(0, Math.min(1, ((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / l2)) : 0;
      return dist(p, [a[0] + t * d[0], a[1] + t * d[1]]);
    };
    const onCut = (p) => cutRing.some((a, i) => segDist(p, a, cutRing[(i + 1) % cutRing.length]) <= TOL_MM);
    const lineDist = (p, a, b) => Math.abs((b[0] - a[0]) * (a[1] - p[1]) - (a[0] - p[0]) * (b[1] - a[1])) / dist(a, b);
    const slits = ents.filter((e) => e.layer === '4' && e.type === 'LINE').map((e) => [[e.vertices[0].x, e.vertices[0].y], [e.vertices[1].x, e.vertices[1].y]]);
    check(`${label}: ${blockName} notches on layer 4: 5 mm slits from the cut line toward the sew line's notches`,
      slits.length === want.notches.length &&
      slits.every(([a, b]) => onCut(a) && Math.abs(dist(a, b) - 5) <= TOL_MM) &&
      want.notches.every((n) => slits.some(([a, b]) => lineDist(n, a, b) <= TOL_MM)));
  }
}

const single = readDxf('skirt_M.dxf');
checkPieces(single, truth.single, 'single-size DXF');

const graded = readDxf('graded.dxf');
checkPieces(graded, truth.graded, 'graded DXF');
check('graded DXF: one block per piece and size', Object.keys(graded.blocks).length === truth.pieces.length * truth.sizes.length,
  `${Object.keys(graded.blocks).length} blocks`);
const sampleBlocks = truth.pieces.map((p) => `${p}_${truth.sample_size}`);
for (const b of sampleBlocks) {
  const texts = graded.blocks[b].entities.filter((e) => e.type === 'TEXT').map((e) => e.text);
  check(`graded DXF: ${b} marked as sample size`, texts.includes(`Sample Size: ${truth.sample_size}`));
}

// ---- RUL against the graded DXF: for each "# N" text in a sample block, the delta of that
// turn point to every size's block must be the RUL's pair N. ---------------------------------
const rul = readFileSync(join(dir, 'graded.rul'), 'latin1').split(/\r\n/);
const sizeList = (rul.find((l) => l.startsWith('SIZE LIST:')) || '').slice(10).trim().split(/\s+/);
check('RUL: size list', JSON.stringify(sizeList) === JSON.stringify(truth.sizes), sizeList.join(' '));
check('RUL: sample size', rul.includes(`SAMPLE SIZE: ${truth.sample_size}`));
const rules = {};
for (let i = 0; i < rul.length; i++) {
  const m = /^RULE: DELTA (\d+)$/.exec(rul[i]);
  if (!m) continue;
  const pairs = [];
  for (let j = i + 1; j < rul.length && !/^(RULE|END)/.test(rul[j]); j++)
    for (const p of rul[j].trim().split(/\s+/).filter(Boolean)) pairs.push(p.split(',').map(Number));
  rules[m[1]] = pairs;
}
let ruleChecks = 0, ruleErr = 0;
for (const piece of truth.pieces) {
  const sample = graded.blocks[`${piece}_${truth.sample_size}`];
  const outline = sample.entities.find((e) => e.layer === '14' && e.type === 'POLYLINE').vertices.map((v) => [v.x, v.y]);
  for (const t of sample.entities.filter((e) => e.type === 'TEXT' && e.layer === '2' && /^# \d+$/.test(e.text))) {
    const n = t.text.slice(2);
    const at = [t.startPoint.x, t.startPoint.y];
    const idx = outline.findIndex((p) => dist(p, at) < 1e-6);
    if (idx < 0 || !rules[n] || rules[n].length !== truth.sizes.length) { ruleErr = Infinity; continue; }
    truth.sizes.forEach((s, k) => {
      const o = graded.blocks[`${piece}_${s}`].entities.find((e) => e.layer === '14' && e.type === 'POLYLINE').vertices;
      const d = [o[idx].x - outline[idx][0], o[idx].y - outline[idx][1]];
      ruleErr = Math.max(ruleErr, dist(d, rules[n][k]));
    });
    ruleChecks++;
  }
}
check(`RUL: ${ruleChecks} rules equal the graded DXF's deltas (max err ${ruleErr.toFixed(4)} mm)`,
  ruleChecks === Object.keys(rules).length && ruleChecks > 0 && ruleErr <= 0.002);

// ---- CSV ------------------------------------------------------------------------------------
function readCsv(file, opts = {}) {
  return parse(readFileSync(join(dir, file), 'utf8'), { columns: true, bom: true, ...opts });
}
const url = (p) => truth.base_url + '/' + p.split('/').map(encodeURIComponent).join('/');
// Every variant a file must hold: the piece (stock 1), then with made-to-order the other sizes.
const variantsOf = (it, mto) => [{ ...it.piece, sku: it.sku, piece: true },
  ...(mto ? it.made_to_order.map((s) => ({ ...s, sku: `${it.sku}-${s.label}`, piece: false })) : [])];
const handleOf = (sku) => sku.toLowerCase().replace(/[^a-z0-9]+/g, '-').replace(/^-+|-+$/g, '');

// No file may link to this machine: a shop cannot fetch from it.
for (const f of ['shopify.csv', 'woocommerce.csv', 'merchant.tsv', 'shopify_mto.csv', 'woocommerce_mto.csv', 'merchant_mto.tsv', 'shopify_legacy.csv'])
  check(`${f}: no loopback link`, !/\/\/(localhost|127\.|\[::1\]|0\.0\.0\.0)/.test(readFileSync(join(dir, f), 'utf8')));

for (const mto of [false, true]) {
  const tag = mto ? 'shopify made-to-order' : 'shopify';
  const shop = readCsv(mto ? 'shopify_mto.csv' : 'shopify.csv');
  for (const it of truth.items) {
    const rows = shop.filter((r) => r['URL handle'] === shop.find((x) => x.Title === it.title)?.['URL handle']);
    check(`${tag}: "${it.title}" found by exact title`, rows.length > 0);
    if (!rows.length) continue;
    const want = variantsOf(it, mto);
    const variants = rows.filter((r) => r.SKU);
    check(`${tag}: ${it.sku} has ${want.length} variants`, variants.length === want.length, `${variants.length}`);
    for (const w of want) {
      const v = variants.find((r) => r.SKU === w.sku);
      check(`${tag}: ${it.sku} variant ${w.label}`, !!v && v['Option1 name'] === 'Size' && v['Option1 value'] === w.label);
      if (!v) continue;
      check(`${tag}: ${w.sku} stock`, w.piece
        ? v['Inventory tracker'] === 'shopify' && v['Inventory quantity'] === '1' && v['Continue selling when out of stock'] === 'DENY'
        : v['Inventory tracker'] === '' && v['Continue selling when out of stock'] === 'CONTINUE');
    }
    const draft = it.price === null;
    check(`${tag}: ${it.sku} ${draft ? 'draft, unpublished' : 'active, published'}`,
      rows[0].Status === (draft ? 'draft' : 'active') && rows[0]['Published on online store'] === (draft ? 'FALSE' : 'TRUE'));
    check(`${tag}: ${it.sku} colour`, rows[0]['Color (product.metafields.shopify.color-pattern)'] === (it.printed ? 'print' : it.color.split('/')[0]));
    check(`${tag}: ${it.sku} vendor is the configured brand`, rows[0].Vendor === truth.brand);
    check(`${tag}: ${it.sku} tags`, rows[0].Tags === it.tags.join(', '));
    check(`${tag}: ${it.sku} images`, JSON.stringify(rows.map((r) => r['Product image URL']).filter(Boolean)) === JSON.stringify(it.images.map(url)));
    const desc = rows[0].Description;
    check(`${tag}: ${it.sku} description holds the piece's size row`,
      desc.includes(`<td>${it.piece.label}</td>`) && Object.values(it.piece.measurements).every((v) => desc.includes(`<td>${fix1(v)}</td>`)));
    check(`${tag}: ${it.sku} guide shows other sizes only when made to order`,
      it.made_to_order.every((s) => desc.includes(`<td>${s.label}</td>`) === mto));
    if (it.price !== null) check(`${tag}: ${it.sku} price`, variants.every((r) => Number(r.Price) === it.price));
  }
}
const legacy = readCsv('shopify_legacy.csv');
check('shopify legacy: Handle/Variant SKU columns', 'Handle' in legacy[0] && 'Variant SKU' in legacy[0]);
check('shopify legacy: titles', truth.items.every((it) => legacy.some((r) => r.Title === it.title)));
check('shopify legacy: the piece tracked with stock 1', truth.items.every((it) => legacy.some((r) => r['Variant SKU'] === it.sku && r['Variant Inventory Qty'] === '1')));

for (const mto of [false, true]) {
  const tag = mto ? 'woocommerce made-to-order' : 'woocommerce';
  const woo = readCsv(mto ? 'woocommerce_mto.csv' : 'woocommerce.csv');
  for (const it of truth.items) {
    const want = variantsOf(it, mto);
    const simple = want.length === 1;
    const parent = woo.find((r) => r.SKU === it.sku && r.Type === (simple ? 'simple' : 'variable'));
    check(`${tag}: ${it.sku} ${simple ? 'simple' : 'variable'} product with exact name`, !!parent && parent.Name === it.title);
    if (!parent) continue;
    check(`${tag}: ${it.sku} ${it.price === null ? 'draft (-1)' : 'published (1)'}`, parent.Published === (it.price === null ? '-1' : '1'));
    check(`${tag}: ${it.sku} short description keeps line breaks`, parent['Short description'] === it.description);
    check(`${tag}: ${it.sku} colour attribute`, parent['Attribute 2 name'] === 'Color' && parent['Attribute 2 value(s)'] === (it.printed ? 'Print' : it.color));
    const rows = simple ? [parent] : woo.filter((r) => r.Type === 'variation' && r.Parent === it.sku);
    check(`${tag}: ${it.sku} ${want.length} sellable rows`, rows.length === want.length, `${rows.length}`);
    for (const w of want) {
      const v = simple ? parent : rows.find((r) => r['Attribute 1 value(s)'] === w.label);
      check(`${tag}: ${it.sku} size ${w.label} Meta measurements`, !!v && Object.entries(w.measurements).every(([k, cm]) => Number(v[`Meta: ${k}_cm`]) === Math.round(cm * 10) / 10));
      if (v) check(`${tag}: ${it.sku} size ${w.label} stock`, w.piece ? v.Stock === '1' && v['Backorders allowed?'] === '0' : v.Stock === '' && v['Backorders allowed?'] === '1');
    }
  }
}

for (const mto of [false, true]) {
  const tag = mto ? 'merchant made-to-order' : 'merchant';
  const gmc = readCsv(mto ? 'merchant_mto.tsv' : 'merchant.tsv', { delimiter: '\t', quote: false });
  for (const it of truth.items) {
    const want = variantsOf(it, mto);
    const rows = gmc.filter((r) => want.some((w) => w.sku === r.id));
    if (it.price === null) {
      check(`${tag}: ${it.sku} without a price is left out`, rows.length === 0);
      continue;
    }
    check(`${tag}: ${it.sku} one row per variant`, rows.length === want.length, `${rows.length}`);
    check(`${tag}: ${it.sku} grouped only when there are variants`, rows.every((r) => r.item_group_id === (want.length > 1 ? it.sku : '')));
    check(`${tag}: ${it.sku} apparel fields`, rows.every((r) => r.gender && r.age_group === 'adult' && r.color === it.color && r.brand === truth.brand && r.size_system === truth.size_system));
    check(`${tag}: ${it.sku} price`, rows.every((r) => r.price === `${it.price.toFixed(2)} EUR`));
    const link = mto ? `${truth.store_url}/product/` : `${truth.store_url}/products/${handleOf(it.sku)}`;
    check(`${tag}: ${it.sku} links to the ${mto ? 'WooCommerce' : 'Shopify'} product page`, rows.every((r) => r.link.startsWith(link) && (!mto || r.link.endsWith('/'))), rows[0]?.link);
    for (const w of want) {
      const r = rows.find((x) => x.id === w.sku);
      check(`${tag}: ${w.sku} size ${w.label} and product_detail`, !!r && r.size === w.label && Object.values(w.measurements).every((cm) => r.product_detail.includes(`:${fix1(cm)} cm`)));
    }
  }
}

console.log(`${passed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
