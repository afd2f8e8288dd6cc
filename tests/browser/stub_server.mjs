// A tiny in-memory stand-in for garmcapd's HTTP API (docs/api.md), used ONLY by the browser test
// when it is run with --stub (no daemon built): it serves daemon/web/ and answers the calls the UI
// makes with the same JSON shapes. It exercises the UI, not the daemon or the exports.
//   node stub_server.mjs PORT WEB_DIR
import { createServer } from 'node:http';
import { readFileSync, existsSync } from 'node:fs';
import { join, extname } from 'node:path';

const [port, webDir] = [Number(process.argv[2]), process.argv[3]];
const TYPES = { '.html': 'text/html; charset=utf-8', '.js': 'text/javascript', '.css': 'text/css', '.svg': 'image/svg+xml' };
const state = { state: 'uncalibrated', calibrated: false, camera: { open: true, backend: 'stub' }, job: null, last_error: '' };
const jobs = [];
const items = [];
const shop = { brand: '', store_url: '', public_base_url: '', store_platform: 'shopify', currency: 'EUR', made_to_order: false };
const sinks = new Set();

function send(res, code, body, type = 'application/json') {
  const data = typeof body === 'string' ? body : JSON.stringify(body);
  res.writeHead(code, { 'Content-Type': type, 'Content-Length': Buffer.byteLength(data) });
  res.end(data);
}
function event(name, data) { for (const s of sinks) s.write(`event: ${name}\ndata: ${JSON.stringify(data)}\n\n`); }
function csv(v) { v = String(v ?? ''); return /[",\r\n]/.test(v) ? '"' + v.replace(/"/g, '""') + '"' : v; }
// The live preview: one still "frame" of a portrait camera (864x1152, as the bundled rig's), a
// form on a green screen; enough for the UI to size the preview box by the frame's aspect.
const PREVIEW_SVG = '<svg xmlns="http://www.w3.org/2000/svg" width="864" height="1152" viewBox="0 0 864 1152"><rect width="864" height="1152" fill="#3a9a3a"/><ellipse cx="432" cy="150" rx="48" ry="60" fill="#d8c8b0"/><path d="M352 230h160l40 300-30 520h-60l-30-400-30 400h-60l-30-520z" fill="#d8c8b0"/></svg>';
const PRODUCT_SVG = '<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 160 200"><path d="M50 10l30 12 30-12 30 40-20 10v130H40V60L20 50z" fill="#4a7fb5"/></svg>';

function runJob(kind, sku) {
  const job = { id: jobs.length + 1, kind, state: 'queued', stage: 'queued', progress: 0, item_id: null, error: '' };
  jobs.push(job);
  const stages = kind === 'empty' ? ['capture', 'calibration'] : ['capture', 'masks', 'measure', 'pattern', 'grading sizes', 'store'];
  // A SKU starting with FAIL makes the capture fail the way a real one does: at a stage, with the
  // pipeline's (developer's) message.
  const failAt = kind === 'dressed' && /^FAIL/.test(sku || '') ? 2 : -1;
  let i = 0;
  state.state = 'capturing';
  const tick = () => {
    if (i === failAt) {
      Object.assign(job, { state: 'failed', stage: stages[i], error: 'garment mask: 0.3 % of the form differs from the bare frame (border median BGR(12,32,9)); no garment found' });
      state.state = 'ready';
      event('job', job);
      event('state', { state: state.state, last_error: '' });
      return;
    }
    if (i < stages.length) {
      Object.assign(job, { state: 'running', stage: stages[i], progress: i / stages.length });
      state.state = i === 0 ? 'capturing' : 'processing';
      event('job', job);
      i++;
      setTimeout(tick, 150);
      return;
    }
    if (kind === 'empty') {
      state.calibrated = true;
    } else {
      const id = items.length + 1;
      const measurements = { bust_circ: 92.4, waist_circ: 76.1, hip_circ: 99.0, hem_circ: 128.2, garment_length: 98.5, sleeve_length: 21.0 };
      items.push({ id, sku: sku || '', title: '', default_title: 'Navy short-sleeve dress', status: 'needs_review', type: 'dress', notes: '', tags: [],
        attributes: { sleeve: 'short', skirt: 'a_line', color: 'Navy', pattern: 'solid' }, confidence: 0.93,
        warnings: ['draft: ease_bust 7.5 is outside the dress recipe\'s range [8.0, 40.0]; drafted with 8.0', 'the garment does not cover the centre front at the waist'],
        checks: ['the garment does not cover the centre front at the waist'],
        price_cents: null, measurements: { ...measurements }, original: { ...measurements }, units: 'cm',
        images: { product: { url: '/stub/product.svg' }, cutout: { url: '/stub/product.svg' } }, sizes: ['base', '55', '66', '77'], base_size: '66',
        created_at: new Date().toISOString() });
      job.item_id = id;
    }
    Object.assign(job, { state: 'done', stage: 'done', progress: 1 });
    state.state = 'ready';
    event('job', job);
    event('state', { state: state.state, last_error: '' });
  };
  setTimeout(tick, 100);
  return job;
}

createServer((req, res) => {
  const url = new URL(req.url, 'http://x');
  const p = url.pathname;
  let body = '';
  req.on('data', (c) => { body += c; });
  // An item answers late, as on a tablet over a slow shop network: the page must not take what
  // staff type before the item has arrived (the form stays off until then).
  req.on('end', () => {
    const slow = req.method === 'GET' && /^\/api\/items\/\d+$/.test(p);
    if (slow) setTimeout(handle, 800); else handle();
  });
  const handle = () => {
    const m = p.match(/^\/api\/items\/(\d+)(\/.*)?$/);
    const item = m ? items.find((x) => x.id === Number(m[1]) && !x.deleted) : null;
    if (p === '/api/status') return send(res, 200, { ...state, calibrated: state.calibrated });
    if (p === '/api/events') {
      res.writeHead(200, { 'Content-Type': 'text/event-stream', 'Cache-Control': 'no-store' });
      res.write(`retry: 2000\n\nevent: status\ndata: ${JSON.stringify(state)}\n\n`);
      sinks.add(res);
      req.on('close', () => sinks.delete(res));
      return;
    }
    if (p === '/stream.mjpg') return send(res, 200, PREVIEW_SVG, 'image/svg+xml');
    if (p === '/stub/product.svg') return send(res, 200, PRODUCT_SVG, 'image/svg+xml');
    if (p === '/api/capture/empty' && req.method === 'POST') return send(res, 202, { job: runJob('empty').id });
    if (p === '/api/capture' && req.method === 'POST') {
      if (!state.calibrated) return send(res, 409, { error: 'the station is not calibrated' });
      const sku = body ? JSON.parse(body).sku : '';
      return send(res, 202, { job: runJob('dressed', sku).id });
    }
    const jm = p.match(/^\/api\/jobs\/(\d+)$/);
    if (jm) { const j = jobs[Number(jm[1]) - 1]; return j ? send(res, 200, j) : send(res, 404, { error: 'no job' }); }
    if (p === '/api/items') {
      const q = (url.searchParams.get('q') || '').toLowerCase();
      const list = items.filter((x) => !x.deleted && (!q || (x.sku + ' ' + x.title).toLowerCase().includes(q)) &&
        (!url.searchParams.get('type') || x.type === url.searchParams.get('type')) &&
        (!url.searchParams.get('status') || x.status === url.searchParams.get('status')));
      return send(res, 200, { items: list, total: list.length });
    }
    if (m && !item) return send(res, 404, { error: 'no item ' + m[1] });
    if (m && !m[2]) {
      if (req.method === 'PATCH') {
        const patch = JSON.parse(body);
        // As the daemon does: measurements replace the names given; the rest replace the field.
        if (patch.measurements) { Object.assign(item.measurements, patch.measurements); delete patch.measurements; }
        Object.assign(item, patch);
        return send(res, 200, item);
      }
      if (req.method === 'DELETE') { item.deleted = true; return send(res, 200, { deleted: item.id }); }
      return send(res, 200, item);
    }
    if (m && m[2] === '/pattern.svg') return send(res, 200, PRODUCT_SVG, 'image/svg+xml');
    if (m && m[2] === '/marker.pdf') {
      // As the station answers while another marker is laid: 503 with Retry-After, then the file.
      if (!state.markerBusyGiven) {
        state.markerBusyGiven = true;
        const data = JSON.stringify({ error: 'another marker is being laid on this station; try again in a few seconds' });
        res.writeHead(503, { 'Content-Type': 'application/json', 'Retry-After': '1', 'Content-Length': Buffer.byteLength(data) });
        return res.end(data);
      }
      const pdf = '%PDF-1.4\n%stub marker\n%%EOF\n';
      res.writeHead(200, { 'Content-Type': 'application/pdf', 'Content-Length': Buffer.byteLength(pdf),
        'Content-Disposition': 'attachment; filename="stub_marker.pdf"' });
      return res.end(pdf);
    }
    if (m && m[2] === '/result.json') return send(res, 200, { type: item.type, measurements: item.original });
    if (m && m[2] === '/sizeguide.json') {
      // The shape of docs/formats.md: the base row is the item's own measurements.
      const names = ['bust_circ', 'waist_circ', 'hip_circ', 'hem_circ', 'garment_length', 'sleeve_length'];
      const rows = ['55', '66', '77'].map((size, k) => ({ size, body: {},
        garment: Object.fromEntries(names.map((n) => [n, item.original[n] + (k - 1) * (n.endsWith('_circ') ? 5 : 1)])) }));
      return send(res, 200, { units: 'cm', type: item.type, chart: 'korean_women', base_size: '66', measurements: names, rows });
    }
    if (m) return send(res, 404, { error: 'not in the stub' });
    if (p === '/api/items/review' && req.method === 'POST') {
      const r = JSON.parse(body);
      const updated = [], missing = [];
      for (const id of r.ids) {
        const x = items.find((i) => i.id === id && !i.deleted);
        if (x) { x.status = r.status; updated.push(id); } else missing.push(id);
      }
      return send(res, 200, { updated, missing });
    }
    if (p === '/api/settings/shop') {
      if (req.method === 'PUT') {
        const r = JSON.parse(body);
        for (const k of ['store_url', 'public_base_url'])
          if (r[k] && !/^https?:\/\//.test(r[k])) return send(res, 400, { error: `shop.${k}: must start with http:// or https://, got '${r[k]}'` });
        Object.assign(shop, r);
      }
      const missing = ['brand', 'store_url', 'public_base_url'].filter((k) => !shop[k]);
      return send(res, 200, { settings: shop, saved: shop, missing });
    }
    if (p === '/api/export/shopify.csv') {
      const baseUrl = url.searchParams.get('base_url') || shop.public_base_url || '';
      if (!baseUrl || /\/\/(localhost|127\.)/.test(baseUrl)) return send(res, 422, { error: "export option 'public_base_url' is empty or this machine; set the shop's public address" });
      const rows = [['Title', 'URL handle', 'SKU', 'Option1 name', 'Option1 value']];
      for (const x of items.filter((i) => i.status === 'approved' && !i.deleted))
        rows.push([x.title, x.sku.toLowerCase(), x.sku, 'Size', x.base_size]);
      res.writeHead(200, { 'Content-Type': 'text/csv', 'Content-Disposition': 'attachment; filename="shopify.csv"' });
      return res.end(rows.map((r) => r.map(csv).join(',')).join('\r\n') + '\r\n');
    }
    if (p.startsWith('/api/')) return send(res, 404, { error: 'not in the stub' });
    const file = join(webDir, p === '/' ? 'index.html' : p.replace(/^\/+/, ''));
    if (!file.startsWith(webDir) || !existsSync(file)) return send(res, 404, { error: 'not found' });
    return send(res, 200, readFileSync(file, 'utf8'), TYPES[extname(file)] || 'application/octet-stream');
  };
}).listen(port, '127.0.0.1');
