// GarmCap web UI, the part the station's UI (app.js) and the hub's (hub.js, served by
// garmcap-hub) share: DOM helpers, names, the API call with its token log-in, measurement and
// size-guide tables. Plain JavaScript, loaded as a classic script before the page's own, so its
// top-level names are the page script's globals. No build step, no dependencies.
'use strict';

const $ = (sel, root = document) => root.querySelector(sel);
const $$ = (sel, root = document) => Array.from(root.querySelectorAll(sel));

const TYPE_NAMES = { top: 'Top', dress: 'Dress', skirt: 'Skirt', pants: 'Pants', '': 'Unknown type' };
const STATUS_NAMES = { needs_review: 'Needs review', approved: 'Approved', rejected: 'Rejected' };
const MEAS_NAMES = {
  bust_circ: 'Bust', waist_circ: 'Waist', hip_circ: 'Hip', hem_circ: 'Hem', garment_length: 'Length',
  skirt_length: 'Skirt length', sleeve_length: 'Sleeve length', outseam: 'Outseam', inseam: 'Inseam',
  leg_opening_circ: 'Leg opening',
};
const MEAS_ORDER = Object.keys(MEAS_NAMES);

// --- API -----------------------------------------------------------------------------------
// A server with a token (a station's, or the hub's admin or station token): the token is asked
// once and exchanged for an HttpOnly session cookie (POST /api/session), which the browser then
// sends on everything, the event stream, the live preview, photos and downloads included. The token is never kept in the page's storage.
// Several calls can meet the 401 at once (the page loads status, items and events together):
// they share one prompt, and a call sent before a log-in that has since succeeded just retries.
// `session.prompt` is the question the page asks; `session.onLogIn` runs after each log-in (the
// station reconnects its event stream and preview there); `session.noAnswer` is the message of a
// server that does not answer.
const session = {
  prompt: 'This station needs its access token (see the station config):',
  onLogIn: () => {},
  noAnswer: 'The station does not answer. Is garmcapd running?',
};
let loginPending = null;
let loginCount = 0;
function logIn(sentAt) {
  if (sentAt !== undefined && sentAt < loginCount) return Promise.resolve(true);
  if (!loginPending) loginPending = doLogIn().finally(() => { loginPending = null; });
  return loginPending;
}

async function doLogIn() {
  const legacy = localStorage.getItem('garmcap.token');
  localStorage.removeItem('garmcap.token');
  const t = legacy || prompt(session.prompt);
  if (!t) return false;
  const res = await fetch('/api/session', {
    method: 'POST', headers: { 'Content-Type': 'application/json' },
    body: JSON.stringify({ token: t.trim() }),
  });
  if (res.ok) {
    loginCount++;
    session.onLogIn();
  }
  return res.ok;
}

async function api(method, path, body, retried) {
  const sentAt = loginCount;
  const opts = { method, headers: {} };
  if (body !== undefined) {
    opts.headers['Content-Type'] = 'application/json';
    opts.body = JSON.stringify(body);
  }
  let res;
  try {
    res = await fetch(path, opts);
  } catch (e) {
    throw new Error(session.noAnswer);
  }
  const text = await res.text();
  let data = null;
  try { data = text ? JSON.parse(text) : null; } catch (e) { data = null; }
  if (res.status === 401 && !retried && await logIn(sentAt)) return api(method, path, body, true);
  if (!res.ok) {
    const msg = (data && data.error) || text || res.statusText;
    const err = new Error(msg);
    err.status = res.status;
    throw err;
  }
  return data;
}

// --- helpers -------------------------------------------------------------------------------
function el(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else if (k.startsWith('on')) e.addEventListener(k.slice(2), v);
    else if (v !== undefined && v !== null && v !== false) e.setAttribute(k, v === true ? '' : v);
  }
  for (const c of children) if (c !== null && c !== undefined) e.append(c);
  return e;
}

// --- downloads -------------------------------------------------------------------------------
// A file fetched (the session cookie goes with it) and saved under the name its
// Content-Disposition gives, so that an error (a bad option, a refused caller) shows as a
// message instead of a saved error file. A busy server says when to come back (503 with
// Retry-After: a station lays one marker at a time, the hub writes two exports at once): wait
// that long, telling staff (`busy`), as garmcapctl does. The export's notes are shown after.
async function downloadFile(href, busy) {
  try {
    const sentAt = loginCount;
    let res = await fetch(href);
    if (res.status === 401 && await logIn(sentAt)) res = await fetch(href);
    for (let attempt = 1; res.status === 503 && res.headers.get('Retry-After') && attempt < 12; ++attempt) {
      const wait = Math.min(30, Math.max(0, Number(res.headers.get('Retry-After')) || 0));
      toast(busy + '; trying again in ' + wait + ' s', false);
      await new Promise((r) => setTimeout(r, wait * 1000));
      res = await fetch(href);
    }
    if (!res.ok) {
      let msg = res.statusText;
      try { msg = (await res.json()).error || msg; } catch (e) { /* not JSON */ }
      throw new Error(msg);
    }
    const blob = await res.blob();
    const cd = res.headers.get('Content-Disposition') || '';
    const m = /filename="([^"]+)"/.exec(cd);
    const url = URL.createObjectURL(blob);
    const link = el('a', { href: url, download: m ? m[1] : 'export' });
    document.body.append(link);
    link.click();
    link.remove();
    setTimeout(() => URL.revokeObjectURL(url), 10000);
    const warned = Number(res.headers.get('X-Export-Warnings') || 0);
    toast('Downloaded ' + (m ? m[1] : 'file') + (warned ? ' — ' + warned + (warned === 1 ? ' note: ' : ' notes: ') + (res.headers.get('X-Export-Warning-Text') || '') : ''), warned > 0);
  } catch (e) { toast('Export failed: ' + e.message, true); }
}

let toastTimer = null;
function toast(msg, bad = false) {
  const t = $('#toast');
  t.textContent = msg;
  t.classList.toggle('bad', bad);
  t.hidden = false;
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => { t.hidden = true; }, bad ? 6000 : 3000);
}

function measName(n) { return MEAS_NAMES[n] || n.replace(/_/g, ' ').replace(/^./, (c) => c.toUpperCase()); }
function cm(v) { return (Math.round(v * 10) / 10).toFixed(1); }
function sortedMeas(m) {
  return Object.keys(m || {}).sort((a, b) => {
    const ia = MEAS_ORDER.indexOf(a), ib = MEAS_ORDER.indexOf(b);
    return (ia < 0 ? 99 : ia) - (ib < 0 ? 99 : ib) || a.localeCompare(b);
  });
}
function measTable(table, m) {
  table.replaceChildren(...sortedMeas(m).map((n) =>
    el('tr', {}, el('td', { text: measName(n) }), el('td', { text: cm(m[n]) + ' cm' }))));
}
function imageUrl(item, kinds) {
  for (const k of kinds) if (item.images && item.images[k]) return item.images[k].url;
  return null;
}
// An empty title is the one the shops get (`default_title`, export_shop.cpp's rule, from the API).
function itemTitle(it) { return it.title || (it.type ? it.default_title : '') || it.sku || 'Item ' + it.id; }

// Why an item is not exported yet, or null when it is approved. Shop exports take approved items
// only (the daemon enforces it); staff must see that before they look for the item in a CSV.
function reviewNote(it) {
  if (it.status === 'needs_review') {
    const why = [];
    if (it.warnings && it.warnings.length) why.push(it.warnings.length + (it.warnings.length === 1 ? ' warning' : ' warnings'));
    else if (it.confidence && it.confidence < 0.8) why.push('low type confidence ' + Math.round(it.confidence * 100) + '%');
    return { title: 'Waiting for review' + (why.length ? ' (' + why.join(', ') + ').' : '.'),
      detail: 'Check the photos, measurements and warnings, then press Approve: only approved items are exported to shops.' };
  }
  if (it.status === 'rejected') return { title: 'Rejected.', detail: 'This item is not exported. Approve it to export it.', rejected: true };
  return null;
}

// A price in cents as the form shows it ("49.90"; "" for none).
function priceText(cents) { return cents == null ? '' : (cents / 100).toFixed(2); }
// What staff typed in a price field: cents, null for an empty field, undefined when it is not a
// price ("49.90", "49,9", "49").
function parsePrice(text) {
  const price = String(text).trim().replace(',', '.');
  if (price === '') return null;
  if (!/^\d+(\.\d{1,2})?$/.test(price)) return undefined;
  return Math.round(parseFloat(price) * 100);
}

// A size guide (the station's sizeguide.json, dsw/size_guide.h: chart, base_size, measurements,
// rows of {size, garment}) as a table; without one, the garment's measurements as measured.
function sizeGuideView(g, measurements) {
  if (g && g.rows && g.measurements) {
    // The guide's own column order (core/dsw); the item's row is the piece itself.
    return [
      el('p', { class: 'muted', text: 'Garment measurements in cm, all the way round for widths. The marked row is this piece; the others are the same design graded to the ' + String(g.chart || '').replace(/_/g, ' ') + ' chart.' }),
      el('div', { class: 'guide-scroll' }, el('table', { class: 'guide' },
        el('thead', {}, el('tr', {}, el('th', { text: 'Size' }), ...g.measurements.map((n) => el('th', { text: measName(n) })))),
        el('tbody', {}, ...g.rows.map((r) => el('tr', { class: r.size === g.base_size ? 'base' : '' },
          el('td', { text: r.size + (r.size === g.base_size ? ' (this piece)' : '') }),
          ...g.measurements.map((n) => el('td', { text: r.garment[n] == null ? '–' : cm(r.garment[n]) })))))))];
  }
  const m = measurements || {};
  return [
    el('p', { class: 'muted', text: 'Not graded yet: the garment as measured.' }),
    el('table', { class: 'guide' },
      el('thead', {}, el('tr', {}, el('th', { text: 'Measurement' }), el('th', { text: 'cm' }))),
      el('tbody', {}, ...sortedMeas(m).map((n) => el('tr', {}, el('td', { text: measName(n) }), el('td', { text: cm(m[n]) })))))];
}
