// GarmCap Hub web UI: the chain's catalog across stations, to read and review (docs/hub.md).
// Plain JavaScript, no build step. common.js (the station's, loaded first) has the DOM helpers,
// names, api() with the token log-in (the token for an HttpOnly session cookie, so the photos,
// blobs at the hub, load in <img>) and the size guide table. The hub's API: /api/items (keyset
// pages: ?after=<next>), /api/items/<id>, PATCH /api/items/<id> (admin: title, price_cents,
// status), /api/hub/stations, /api/session, and the chain's exports (/api/export/..., through
// the session cookie).
'use strict';

session.prompt = 'The hub needs a token: the admin token to review, or a station\'s to read its items:';
session.noAnswer = 'The hub does not answer. Is garmcap-hub running?';
session.onLogIn = () => whoAmI();

const PAGE = 24;
const hub = {
  role: null,        // "admin", "station" or null (GET /api/session)
  catalog: { q: '', station: '', status: '', next: null, shown: 0 },
  item: null,
  photoKind: null,
  loadSeq: 0,        // the newest catalog request; older answers are dropped
  exportStations: [], // the export page's stations with their counts by status
};
const picked = new Set();

function showBanner(title, detail) {
  $('#banner-title').textContent = title;
  $('#banner-detail').textContent = detail || '';
  $('#banner').hidden = false;
}

// Who this browser is at the hub: the admin reviews; a station token reads its own items only.
// The session's answer, or null when the hub does not answer.
async function whoAmI() {
  try {
    const s = await api('GET', '/api/session');
    hub.role = s.role;
    $('#who-text').textContent = s.role === 'admin' ? 'Admin' : s.role === 'station' ? 'Station ' + s.station : 'Not signed in';
    $('#who').dataset.state = s.authenticated ? 'ready' : 'unknown';
    document.body.classList.toggle('read-only', s.role !== 'admin');
    $('#banner').hidden = true;
    return s;
  } catch (e) {
    $('#who').dataset.state = 'offline';
    $('#who-text').textContent = 'Hub offline';
    showBanner('Hub offline.', e.message);
    return null;
  }
}

// The station filter: every station the hub knows, with its item count.
async function loadStations() {
  try {
    const r = await api('GET', '/api/hub/stations');
    const sel = $('#station-filter');
    const total = r.stations.reduce((n, s) => n + s.items, 0);
    sel.replaceChildren(el('option', { value: '', text: 'All stations (' + total + ')' }),
      ...r.stations.map((s) => el('option', { value: s.id, text: s.id + ' (' + s.items + ')' })));
    sel.value = r.stations.some((s) => s.id === hub.catalog.station) ? hub.catalog.station : '';
  } catch (e) { toast(e.message, true); }
}

// --- catalog ---------------------------------------------------------------------------------
async function loadCatalog(reset) {
  const c = hub.catalog;
  // A new list also refreshes the stations and their counts (a station may have joined).
  if (reset) { c.next = null; c.shown = 0; loadStations(); }
  const params = new URLSearchParams({ limit: String(PAGE) });
  if (!reset && c.next) params.set('after', String(c.next));
  if (c.q) params.set('q', c.q);
  if (c.station) params.set('station', c.station);
  if (c.status) params.set('status', c.status);
  const seq = ++hub.loadSeq;
  try {
    const r = await api('GET', '/api/items?' + params);
    if (seq !== hub.loadSeq) return;  // a newer filter or search was asked for meanwhile
    const tiles = r.items.map(tile);
    if (reset) $('#grid').replaceChildren(...tiles); else $('#grid').append(...tiles);
    c.next = r.next;
    c.shown += r.items.length;
    if (reset && !r.items.length)
      $('#grid').replaceChildren(el('div', { class: 'empty', text: c.q || c.station || c.status ? 'No item matches.' : 'No station has sent an item yet.' }));
    $('#count').textContent = c.shown + (c.shown === 1 ? ' item' : ' items') + (c.next ? ' shown, more below' : '');
    $('#more').hidden = !c.next;
  } catch (e) { toast(e.message, true); }
}

function updateBulk() {
  const b = $('#bulk-approve');
  b.hidden = picked.size === 0;
  b.textContent = 'Approve selected (' + picked.size + ')';
}

// The hub has no bulk route: one PATCH per item, a few at a time, and what failed is said.
async function approvePicked() {
  const ids = Array.from(picked);
  const failed = [];
  let done = 0;
  $('#bulk-approve').disabled = true;
  const worker = async () => {
    while (ids.length) {
      const id = ids.shift();
      try { await api('PATCH', '/api/items/' + id, { status: 'approved' }); done++; picked.delete(id); } catch (e) { failed.push(id + ': ' + e.message); }
    }
  };
  await Promise.all([worker(), worker(), worker(), worker()]);
  $('#bulk-approve').disabled = false;
  if (failed.length) toast('Approved ' + done + '; not approved ' + failed.join('; '), true);
  else toast('Approved ' + done + (done === 1 ? ' item' : ' items'));
  updateBulk();
  loadCatalog(true);
}

function tile(it) {
  const src = imageUrl(it, ['product_4x5', 'product', 'cutout', 'dressed']);
  const pick = it.status === 'approved' ? null : el('label', { class: 'pick review-only', title: 'Select to approve', onclick: (e) => e.stopPropagation() },
    el('input', { type: 'checkbox', 'data-id': it.id, checked: picked.has(it.id), onchange: (e) => {
      if (e.target.checked) picked.add(it.id); else picked.delete(it.id);
      updateBulk();
    } }));
  const price = priceText(it.price_cents);
  return el('div', { class: 'tile-wrap' }, pick,
    el('a', { class: 'tile', href: '#/item/' + it.id, 'data-id': it.id, 'data-station': it.station },
      el('div', { class: 'img' }, src ? el('img', { src, alt: itemTitle(it), loading: 'lazy' }) : el('span', { class: 'muted', text: 'No photo' })),
      el('div', { class: 'txt' },
        el('div', { class: 't', text: itemTitle(it) }),
        el('div', { class: 's' }, el('span', { text: (TYPE_NAMES[it.type] || it.type) + (it.sku ? ' · ' + it.sku : '') }),
          el('span', { class: 'badge ' + it.status, text: STATUS_NAMES[it.status] || it.status })),
        el('div', { class: 's2' }, el('span', { class: 'station-tag', text: it.station }),
          el('span', { class: 'price', text: price || 'no price' })))));
}

// --- item page -------------------------------------------------------------------------------
// The station's own fields (warnings, size guide, notes) come with the hub's item as it pushed
// them (station_item).
async function loadItem(id) {
  let it;
  const form = $('#item-form');
  form.setAttribute('aria-busy', 'true');
  for (const c of form.querySelectorAll('input, button')) c.disabled = true;
  try { it = await api('GET', '/api/items/' + id); } catch (e) {
    toast(e.status === 404 ? 'Item ' + id + ' is not at the hub.' : e.message, true);
    location.hash = '#/catalog';
    return;
  }
  hub.item = it;
  const st = it.station_item || {};
  const view = Object.assign({}, st, it);  // the hub's columns over the station's JSON
  $('#item-title').textContent = itemTitle(view);
  const badge = $('#item-status');
  badge.className = 'badge ' + it.status;
  badge.textContent = STATUS_NAMES[it.status] || it.status;
  $('#item-station').textContent = 'from ' + it.station;
  $('#f-title').value = it.title || '';
  $('#f-title').placeholder = st.default_title || '';
  $('#f-price').value = priceText(it.price_cents);
  // docs/hub.md, "Who owns what": until approval the station owns every field, and the hub may
  // only approve (with a title and price); from then on title, price and status are the hub's.
  $('#owner-note').textContent = it.hub_owned
    ? 'Title, price and status are the hub\'s: a change here goes back to station ' + it.station + '.'
    : 'Station ' + it.station + ' owns this item until it is approved: approve it here (with the title and price above), or correct or reject it at the station.';
  $('#f-save').hidden = !it.hub_owned;
  $('#f-approve').hidden = it.status === 'approved';
  $('#f-reject').hidden = !it.hub_owned || it.status === 'rejected';
  const note = reviewNote(view);
  $('#item-review').hidden = !note;
  $('#item-review').classList.toggle('rejected', !!(note && note.rejected));
  $('#item-review-title').textContent = note ? note.title : '';
  $('#item-review-detail').textContent = note ? note.detail : '';
  $('#f-msg').textContent = '';
  const at = (t) => (t || '').replace('T', ' ').replace(/(\.\d+)?(Z|\+00(:00)?)$/, ' UTC');
  $('#item-facts').replaceChildren(...[
    ['Station', it.station + ' (its item ' + it.local_id + ')'],
    ['Hub id', String(it.id)],
    ['SKU', it.sku || '–'],
    ['Type', TYPE_NAMES[it.type] || it.type || '–'],
    ['Fits size', st.base_size || '–'],
    ['Received', at(it.created_at)],
    ['Changed', at(it.updated_at)],
  ].map(([k, v]) => el('tr', {}, el('td', { text: k }), el('td', { text: v }))));
  // The station said which warnings are checks (docs/api.md, "checks"); an older station did not.
  const checks = Array.isArray(st.checks) ? new Set(st.checks) : null;
  $('#item-warn').replaceChildren(...(st.warnings || []).map((w) =>
    el('li', { text: (!checks || checks.has(w) ? 'Check: ' : 'Note: ') + w })));
  const kinds = ['product_4x5', 'product', 'cutout', 'dressed', 'overlay', 'texture'].filter((k) => it.images && it.images[k]);
  for (const k of Object.keys(it.images || {})) if (!kinds.includes(k)) kinds.push(k);
  hub.photoKind = kinds[0] || null;
  $('#thumbs').replaceChildren(...kinds.map((k) => el('button', {
    type: 'button', 'data-kind': k, onclick: () => { hub.photoKind = k; showPhoto(); },
  }, el('img', { src: it.images[k].url, alt: k }), k)));
  showPhoto();
  measTable($('#item-meas'), it.measurements);
  $('#sizeguide').replaceChildren(...sizeGuideView(st.size_guide, it.measurements));
  form.setAttribute('aria-busy', 'false');
  for (const c of form.querySelectorAll('input, button')) c.disabled = false;
}

function showPhoto() {
  const it = hub.item;
  $$('#thumbs button').forEach((b) => b.classList.toggle('on', b.dataset.kind === hub.photoKind));
  $('#photos').replaceChildren(hub.photoKind ? el('img', { src: it.images[hub.photoKind].url, alt: hub.photoKind + ' photo' })
    : el('span', { class: 'muted', text: 'No photos' }));
}

// The form's title and price where they differ from the item's; undefined when the price is not
// one.
function formChanges() {
  const it = hub.item;
  const body = {};
  const title = $('#f-title').value.trim();
  if (title !== (it.title || '')) body.title = title;
  const price = parsePrice($('#f-price').value);
  if (price === undefined) { toast('Price: a number like 49.90', true); return undefined; }
  if (price !== it.price_cents) body.price_cents = price;
  return body;
}

async function patchItem(body, done) {
  try {
    await api('PATCH', '/api/items/' + hub.item.id, body);
    $('#f-msg').textContent = done + ' ✓';
    toast(done);
    loadItem(hub.item.id);
  } catch (e) { toast(e.message, true); }
}

// --- export ----------------------------------------------------------------------------------
// The chain's shop files and catalog.zip, of every station or one (a station's token: its own),
// downloaded through fetch with the session cookie. The shop files hold approved items only (the
// review gate, as at the station): the page says how many that is for the station chosen, and
// how many waiting for review or rejected are left out, from /api/hub/stations' counts. The
// shop links are options of the download; left empty, the hub's [shop] settings apply.
const EXPORT_OPTIONS = ['base_url', 'store_url', 'brand'];
const EXPORT_KEY = 'garmcap.hub.export';

function exportOptions() {
  const o = {};
  for (const k of EXPORT_OPTIONS) {
    const v = $('#x-' + k).value.trim();
    if (v) o[k] = v;
  }
  return o;
}

function updateExportLinks() {
  const o = exportOptions();
  localStorage.setItem(EXPORT_KEY, JSON.stringify(Object.assign({ legacy: $('#x-legacy').checked }, o)));
  const station = $('#x-station').value;
  for (const a of $$('#view-export .export-buttons a')) {
    const params = new URLSearchParams(o);
    if (station) params.set('station', station);
    if (a.dataset.file === 'shopify.csv' && $('#x-legacy').checked) params.set('legacy', '1');
    const q = params.toString();
    a.href = '/api/export/' + a.dataset.file + (q ? '?' + q : '');
  }
}

// The stations to export from, with how many of their items a shop file holds.
async function loadExport() {
  let r;
  try { r = await api('GET', '/api/hub/stations'); } catch (e) { $('#x-count').textContent = e.message; return; }
  hub.exportStations = r.stations;
  const sel = $('#x-station');
  const keep = sel.value;
  const all = hub.role === 'admin' ? [el('option', { value: '', text: 'All stations' })] : [];
  sel.replaceChildren(...all, ...r.stations.map((s) => el('option', { value: s.id, text: s.id })));
  const values = Array.from(sel.options).map((o) => o.value);
  sel.value = values.includes(keep) ? keep : (values[0] || '');
  updateExportLinks();
  showExportCount();
}

function showExportCount() {
  const station = $('#x-station').value;
  const chosen = hub.exportStations.filter((s) => !station || s.id === station);
  const n = (k) => chosen.reduce((sum, s) => sum + ((s.statuses || {})[k] || 0), 0);
  const approved = n('approved'), waiting = n('needs_review'), rejected = n('rejected');
  const left = [];
  if (waiting) left.push(waiting + ' waiting for review');
  if (rejected) left.push(rejected + ' rejected');
  const c = $('#x-count');
  c.dataset.approved = String(approved);
  c.textContent = approved + ' approved item' + (approved === 1 ? '' : 's') + (station ? ' of ' + station : ' of every station') +
    ' will be exported' + (left.length ? '; ' + left.join(' and ') + (waiting + rejected === 1 ? ' is' : ' are') + ' left out until approved.' : '.');
}

function currentView() { return (location.hash.match(/^#\/(\w+)/) || [])[1] || 'catalog'; }
function route() {
  const view = currentView();
  $$('.view').forEach((v) => { v.hidden = v.dataset.view !== view; });
  $$('.tabs a').forEach((a) => a.classList.toggle('on', a.dataset.tab === view || (view === 'item' && a.dataset.tab === 'catalog')));
  if (view === 'catalog') loadCatalog(true);
  if (view === 'item') loadItem((location.hash.match(/^#\/item\/(\d+)/) || [])[1]);
  if (view === 'export') loadExport();
}

async function init() {
  let searchTimer = null;
  $('#search').addEventListener('input', () => {
    clearTimeout(searchTimer);
    searchTimer = setTimeout(() => { hub.catalog.q = $('#search').value.trim(); loadCatalog(true); }, 250);
  });
  $('#station-filter').addEventListener('change', (e) => { hub.catalog.station = e.target.value; loadCatalog(true); });
  $('#status-filter').addEventListener('change', (e) => { hub.catalog.status = e.target.value; loadCatalog(true); });
  $('#more').addEventListener('click', () => loadCatalog(false));
  $('#bulk-approve').addEventListener('click', approvePicked);
  $('#item-form').addEventListener('submit', (ev) => {
    ev.preventDefault();
    const body = formChanges();
    if (body === undefined) return;
    if (!Object.keys(body).length) { toast('Nothing changed'); return; }
    patchItem(body, 'Saved');
  });
  $('#f-approve').addEventListener('click', () => {
    const body = formChanges();
    if (body !== undefined) patchItem(Object.assign(body, { status: 'approved' }), 'Approved');
  });
  $('#f-reject').addEventListener('click', () => patchItem({ status: 'rejected' }, 'Rejected: it will not be exported'));
  try {
    const saved = JSON.parse(localStorage.getItem(EXPORT_KEY) || '{}');
    for (const k of EXPORT_OPTIONS) $('#x-' + k).value = saved[k] || '';
    $('#x-legacy').checked = !!saved.legacy;
  } catch (e) { /* nothing kept */ }
  $('#x-options').addEventListener('input', updateExportLinks);
  $('#x-options').addEventListener('change', updateExportLinks);
  $('#x-options').addEventListener('submit', (ev) => ev.preventDefault());
  $('#x-station').addEventListener('change', () => { updateExportLinks(); showExportCount(); });
  $$('#view-export .export-buttons a').forEach((a) => a.addEventListener('click', (ev) => {
    ev.preventDefault();
    downloadFile(a.href, 'The hub is writing other exports');
  }));
  window.addEventListener('hashchange', route);
  // Who this is first: a browser without a session is asked for the token once, before the
  // page's calls would each meet a 401.
  const s = await whoAmI();
  if (s && !s.authenticated) await logIn();
  route();
}

document.addEventListener('DOMContentLoaded', init);
