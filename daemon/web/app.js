// GarmCap Station web UI: plain JavaScript, no build step, no dependencies. Talks to the HTTP API
// of garmcapd (docs/api.md): status and job progress through server-sent events (/api/events),
// live preview as MJPEG (/stream.mjpg), the catalog through /api/items, exports via /api/export.
// common.js (loaded first, shared with the hub's UI) has the DOM helpers, names, api() and the
// token log-in.
'use strict';

const STATE_NAMES = {
  ready: 'Ready', capturing: 'Capturing…', processing: 'Processing…', uncalibrated: 'Not calibrated',
  error: 'Error', stopping: 'Stopping', offline: 'Station offline', unknown: 'Connecting…',
};
const STAGE_NAMES = {
  queued: 'Waiting', capture: 'Taking the photo', registration: 'Checking the camera',
  masks: 'Finding the garment', grabcut: 'Cutting out', type: 'Recognising the type',
  landmarks: 'Finding landmarks', measure: 'Measuring', garmcap: 'Measuring', pattern: 'Drafting the pattern',
  grading: 'Grading sizes', 'grading sizes': 'Grading sizes', images: 'Making product photos', store: 'Saving',
  texture: 'Reading the fabric', context: 'Preparing', calibration: 'Calibrating', 'form model': 'Loading the form', capturing: 'Taking the photo', processing: 'Measuring',
};
// The palette the station names colours with (daemon garment_colour.cpp), for the colour field.
const COLOUR_NAMES = ['Black', 'White', 'Grey', 'Beige', 'Cream', 'Brown', 'Red', 'Burgundy', 'Pink', 'Orange',
  'Yellow', 'Green', 'Olive', 'Turquoise', 'Light blue', 'Blue', 'Navy', 'Purple'];
function stageName(stage) {
  if (!stage) return 'Working';
  if (STAGE_NAMES[stage]) return STAGE_NAMES[stage];
  const s = String(stage).replace(/_/g, ' ');
  return s.charAt(0).toUpperCase() + s.slice(1);
}

// A failed capture in plain words with what to do next; the raw message goes to "details".
function plainFailure(error) {
  const e = String(error || '');
  // A refused back shot (the library's sentence starts so): the item is as it was.
  if (/^the back shot/i.test(e))
    return { what: 'The back shot was refused; the item is unchanged.', next: 'Put the same garment on the form turned back to front, without moving the camera, and press Take back shot again.' };
  if (/camera|disconnect|timed out|timeout|no frame|device/i.test(e))
    return { what: 'The camera did not deliver a photo.', next: 'Check the camera cable and power, then press Capture garment again.' };
  if (/not calibrated|calibrat|bare.form|registration|shift/i.test(e))
    return { what: 'The station could not find the form in the photo.', next: 'Take the garment off, press Capture bare form, dress the form again and capture.' };
  if (/no garment|garment.*(not|no) |nothing|empty|silhouette|mask|too small/i.test(e))
    return { what: 'No garment was found on the form.', next: 'Put the garment on the form facing the camera, smooth it, and press Capture garment again.' };
  return { what: 'The garment could not be measured.', next: 'Check that the garment sits straight on the form and nothing stands in front of the camera, then press Capture garment again.' };
}

// Warnings that need a person say what to check; the rest are notes that do not block. The
// station decides which is which (the item's `checks`, daemon/src/review_policy.cpp); without
// them (an older station) every warning is a check.
function splitWarnings(list, checkList) {
  const all = list || [];
  if (!Array.isArray(checkList)) return { checks: all.slice(), notes: [] };
  const isCheck = new Set(checkList);
  return { checks: all.filter((w) => isCheck.has(w)), notes: all.filter((w) => !isCheck.has(w)) };
}
function checkText(w) {
  if (/type|silhouette|IoU/i.test(w)) return 'Check the garment type: ' + w;
  if (/hem|waist|centre front|crotch|leg/i.test(w)) return 'Check the measurements on the garment: ' + w;
  if (/size guide|graded/i.test(w)) return 'Check the sizes: ' + w;
  return 'Check: ' + w;
}
function showWarnings(listEl, notesEl, warnings, checkList) {
  const { checks, notes } = splitWarnings(warnings, checkList);
  listEl.replaceChildren(...checks.map((w) => el('li', { text: checkText(w) })));
  notesEl.replaceChildren(...notes.map((w) => el('li', { text: 'Note: ' + w })));
}

const ui = {
  status: null,
  job: null,          // the job in hand (latest job event)
  lastItemId: null,
  catalog: { q: '', type: '', status: '', offset: 0, total: 0 },
  item: null,
  itemSize: 'base',
  photoKind: null,
};

// --- station status, errors, events ---------------------------------------------------------
function showBanner(title, detail, kind = 'bad', action = null) {
  const b = $('#banner');
  b.classList.toggle('warn', kind === 'warn');
  $('#banner-title').textContent = title;
  $('#banner-detail').textContent = detail || '';
  const btn = $('#banner-action');
  if (action) {
    btn.textContent = action.label;
    btn.onclick = action.run;
    btn.hidden = false;
  } else {
    btn.hidden = true;
  }
  b.hidden = false;
}
function hideBanner() { $('#banner').hidden = true; }

// Buttons that change the catalog or the station (off while the station is read-only).
const WRITE_CONTROLS = ['last-approve', 'bulk-approve', 'f-save', 'f-approve', 'f-reject',
  'btn-rerun', 'btn-back', 'btn-delete', 's-save'];

function applyStatus(s) {
  ui.status = Object.assign(ui.status || {}, s);
  const st = ui.status;
  const state = st.state || 'unknown';
  $('#state').dataset.state = state;
  $('#state-text').textContent = STATE_NAMES[state] || state;
  const cam = st.camera || {};
  const busy = state === 'capturing' || state === 'processing';
  // Started on a full disk, the station serves what it has and refuses every write (507):
  // say so once, and turn off every control that would only fail.
  const readOnly = st.read_only === true;
  document.body.classList.toggle('read-only', readOnly);
  for (const id of WRITE_CONTROLS) {
    const el = $('#' + id);
    if (el) el.disabled = readOnly || el.closest('[aria-busy="true"]') !== null;
  }
  $('#btn-capture').disabled = readOnly || !st.calibrated || cam.open === false || state === 'error' || state === 'stopping';
  $('#btn-empty').disabled = readOnly || cam.open === false || state === 'stopping';
  $('#btn-capture').textContent = busy ? 'Capturing…' : 'Capture garment';
  $('#btn-capture').classList.toggle('busy', busy);
  if (readOnly) {
    showBanner('Read-only: the disk is full.', st.last_error ||
      'Free space in the station\'s data folder, then restart the station.');
  } else if (cam.open === false) {
    showBanner('Camera not found.', (cam.error ? cam.error + ' — ' : '') +
      'Check the camera cable and power, then wait: the station retries by itself.');
  } else if (!st.calibrated) {
    showBanner('Form not calibrated.', 'Remove any garment from the form, then capture the bare form once.',
      'warn', { label: 'Capture bare form', run: captureEmpty });
  } else if (state === 'error' && st.last_error) {
    showBanner('Station error.', st.last_error);
  } else {
    hideBanner();
  }
  if (st.job) applyJob(st.job);
}

function applyJob(job) {
  if (!job || !job.id) return;
  if (ui.job && ui.job.id > job.id) return;  // an older job's late event
  ui.job = Object.assign({}, ui.job && ui.job.id === job.id ? ui.job : {}, job);
  const j = ui.job;
  const box = $('#job');
  // A finished garment capture is shown by its result card; the job card is for progress and failures.
  box.hidden = j.state === 'done' && j.kind === 'dressed';
  $('.capture-grid').classList.add('has-result');
  box.classList.toggle('failed', j.state === 'failed');
  box.classList.toggle('done', j.state === 'done');
  const kind = j.kind === 'empty' ? 'Bare-form capture' : j.kind === 'rerun' ? 'Re-run'
    : j.kind === 'back' ? 'Back shot' : 'Garment capture';
  $('#job-title').textContent = kind + ' #' + j.id;
  const stage = j.state === 'done' ? 'Done' : j.state === 'failed' ? 'Failed'
    : j.state === 'queued' ? 'Waiting' : stageName(j.stage);
  $('#job-stage').textContent = stage;
  const p = j.state === 'done' ? 1 : Math.max(0, Math.min(1, j.progress || 0));
  $('#job-bar').style.width = Math.round(p * 100) + '%';
  $('#job-bar').parentElement.setAttribute('aria-valuenow', String(Math.round(p * 100)));
  const err = $('#job-error');
  err.hidden = j.state !== 'failed';
  if (j.state === 'failed') {
    const f = plainFailure(j.error);
    $('#job-error-what').textContent = f.what;
    $('#job-error-next').textContent = 'What to do: ' + f.next;
    $('#job-error-detail').textContent = j.error || '';
    if (!j.toasted) { j.toasted = true; toast('Capture failed. ' + f.what, true); }
    $('#last').hidden = true;  // the last result is not this garment's
  }
  if (j.state === 'done' && j.item_id && j.item_id !== ui.lastItemId) {
    ui.lastItemId = j.item_id;
    if (j.kind !== 'rerun' && j.kind !== 'back') $('#sku').value = '';  // the SKU belonged to this garment
    showLastResult(j.item_id);
    if (currentView() === 'catalog') loadCatalog(true);
  }
  // A back shot of the item on screen: show its new photos.
  if (j.state === 'done' && j.kind === 'back' && !j.notified) {
    j.notified = true;
    toast('Back shot added.');
    if (ui.item && ui.item.id === j.item_id && currentView() === 'item') loadItem(j.item_id);
  }
  if (j.state === 'done' && j.kind === 'empty' && !j.notified) {
    j.notified = true;
    toast('Form calibrated. Ready for garments.');
    refreshStatus();
  }
}

async function refreshStatus() {
  try {
    applyStatus(await api('GET', '/api/status'));
  } catch (e) {
    applyStatus({ state: 'offline' });
    showBanner('Station offline.', e.message);
  }
}

let events = null;
// What loaded before a log-in (events, preview) starts again after it.
session.onLogIn = () => {
  if (events) { events.close(); connectEvents(); }
  const preview = document.querySelector('#preview');
  if (preview && preview.getAttribute('src')) preview.src = '/stream.mjpg?t=' + Date.now();
};
function connectEvents() {
  if (events) events.close();
  events = new EventSource('/api/events');
  events.addEventListener('status', (e) => applyStatus(JSON.parse(e.data)));
  events.addEventListener('state', (e) => applyStatus(JSON.parse(e.data)));
  events.addEventListener('job', (e) => applyJob(JSON.parse(e.data)));
  events.onerror = () => {
    if (events.readyState === EventSource.CLOSED) setTimeout(connectEvents, 3000);
    refreshStatus();
  };
}

// Job polling as a fallback: events may be lost behind a proxy; the job's state is what counts.
setInterval(async () => {
  if (!ui.job || ui.job.state === 'done' || ui.job.state === 'failed') return;
  try { applyJob(await api('GET', '/api/jobs/' + ui.job.id)); } catch (e) { /* status shows it */ }
}, 1500);

// --- capture --------------------------------------------------------------------------------
// One tap, one capture: a second tap while the photo is being taken (or within a moment of the
// first) would capture the same garment twice.
let captureInFlight = false, lastCaptureAt = 0;
function photoPending() {
  const j = ui.job;
  return !!j && j.kind === 'dressed' && (j.state === 'queued' || (j.state === 'running' && (j.stage === 'capture' || j.stage === 'capturing')));
}
async function captureGarment() {
  // The 2 s guard is for a double tap on one garment; once that capture has finished, a tap is the
  // next garment's (the stub station finishes within the 2 s, and a fast one may too).
  const finished = !!ui.job && (ui.job.state === 'done' || ui.job.state === 'failed');
  if (captureInFlight || (Date.now() - lastCaptureAt < 2000 && !finished) || photoPending()) {
    toast('Already capturing this garment: wait for the result.');
    return;
  }
  const sku = $('#sku').value.trim();
  if (sku && !/^[A-Za-z0-9._-]{1,64}$/.test(sku)) {
    toast('A SKU may hold only letters, digits, dot, dash and underscore.', true);
    return;
  }
  captureInFlight = true;
  lastCaptureAt = Date.now();
  $('#btn-capture').disabled = true;
  try {
    const r = await api('POST', '/api/capture', sku ? { sku } : {});
    $('#last').hidden = true;
    applyJob({ id: r.job, state: 'queued', kind: 'dressed', progress: 0 });
  } catch (e) {
    toast(e.status === 409 ? 'Form not calibrated: capture the bare form first.' : 'Capture not started: ' + e.message, true);
  } finally {
    captureInFlight = false;
    if (ui.status) applyStatus({});
  }
}
async function captureEmpty() {
  try {
    const r = await api('POST', '/api/capture/empty');
    applyJob({ id: r.job, state: 'queued', kind: 'empty', progress: 0 });
    location.hash = '#/capture';
  } catch (e) { toast(e.message, true); }
}

async function showLastResult(id) {
  try {
    const it = await api('GET', '/api/items/' + id);
    $('#last').hidden = false;
    $('#last-img').src = imageUrl(it, ['product_4x5', 'product', 'cutout']) || '';
    $('#last-type').textContent = itemTitle(it);
    $('#last-sku').textContent = (it.sku ? 'SKU ' + it.sku + ' · ' : 'No SKU · ') + (STATUS_NAMES[it.status] || it.status) +
      (it.base_size ? ' · fits size ' + it.base_size : '');
    measTable($('#last-meas'), it.measurements);
    showWarnings($('#last-warn'), $('#last-notes'), it.warnings, it.checks);
    const note = reviewNote(it);
    $('#last-review').hidden = !note;
    $('#last-review').textContent = note ? note.title + ' Approve it to export it.' : '';
    $('#last-approve').hidden = it.status === 'approved';
    $('#last-approve').onclick = async () => {
      try { await api('PATCH', '/api/items/' + id, { status: 'approved' }); toast('Approved'); showLastResult(id); } catch (e) { toast(e.message, true); }
    };
    $('#last-open').onclick = () => { location.hash = '#/item/' + id; };
    // Result and Approve in view, whatever the screen: staff should not have to scroll for them.
    requestAnimationFrame(() => $('#last').scrollIntoView({ block: 'nearest' }));
  } catch (e) { toast(e.message, true); }
}

// --- catalog --------------------------------------------------------------------------------
let searchTimer = null;
async function loadCatalog(reset) {
  const c = ui.catalog;
  if (reset) c.offset = 0;
  const params = new URLSearchParams({ limit: '24', offset: String(c.offset) });
  if (c.q) params.set('q', c.q);
  if (c.type) params.set('type', c.type);
  if (c.status) params.set('status', c.status);
  try {
    const r = await api('GET', '/api/items?' + params);
    c.total = r.total;
    const tiles = r.items.map(tile);
    if (reset) $('#grid').replaceChildren(...tiles); else $('#grid').append(...tiles);
    c.offset += r.items.length;
    if (reset && !r.items.length)
      $('#grid').replaceChildren(el('div', { class: 'empty', text: c.q || c.type || c.status ? 'No item matches.' : 'The catalog is empty. Capture a garment to start.' }));
    $('#count').textContent = r.total + (r.total === 1 ? ' item' : ' items');
    $('#more').hidden = c.offset >= r.total;
  } catch (e) { toast(e.message, true); }
}
const picked = new Set();
function updateBulk() {
  const b = $('#bulk-approve');
  b.hidden = picked.size === 0;
  b.textContent = 'Approve selected (' + picked.size + ')';
}
async function approvePicked() {
  const ids = Array.from(picked);
  try {
    const r = await api('POST', '/api/items/review', { ids, status: 'approved' });
    toast('Approved ' + r.updated.length + (r.updated.length === 1 ? ' item' : ' items'));
    picked.clear();
    updateBulk();
    loadCatalog(true);
  } catch (e) { toast('Not approved: ' + e.message, true); }
}
function tile(it) {
  const src = imageUrl(it, ['product', 'cutout', 'dressed']);
  const pick = it.status === 'approved' ? null : el('label', { class: 'pick', title: 'Select to approve', onclick: (e) => e.stopPropagation() },
    el('input', { type: 'checkbox', 'data-id': it.id, checked: picked.has(it.id), onchange: (e) => {
      if (e.target.checked) picked.add(it.id); else picked.delete(it.id);
      updateBulk();
    } }));
  return el('div', { class: 'tile-wrap' }, pick, tileLink(it, src));
}
function tileLink(it, src) {
  return el('a', { class: 'tile', href: '#/item/' + it.id, 'data-id': it.id },
    el('div', { class: 'img' }, src ? el('img', { src, alt: itemTitle(it), loading: 'lazy' }) : el('span', { class: 'muted', text: 'No photo' })),
    el('div', { class: 'txt' },
      el('div', { class: 't', text: itemTitle(it) }),
      el('div', { class: 's' }, el('span', { text: (TYPE_NAMES[it.type] || it.type) + (it.sku ? ' · ' + it.sku : '') }),
        el('span', { class: 'badge ' + it.status, text: STATUS_NAMES[it.status] || it.status }))));
}

// --- item page ------------------------------------------------------------------------------
// While an item loads its form is off: whatever staff typed before the item arrived would be
// overwritten by the stored values (and a save would go to the item shown before).
function setItemFormLoading(loading) {
  const form = $('#item-form');
  form.setAttribute('aria-busy', loading ? 'true' : 'false');
  const readOnly = document.body.classList.contains('read-only');
  for (const c of form.querySelectorAll('input, select, textarea, button')) {
    c.disabled = loading || (readOnly && WRITE_CONTROLS.includes(c.id));
  }
}
async function loadItem(id) {
  let it;
  setItemFormLoading(true);
  try { it = await api('GET', '/api/items/' + id); } catch (e) {
    toast(e.status === 404 ? 'Item ' + id + ' does not exist (deleted?).' : e.message, true);
    location.hash = '#/catalog';
    return;
  }
  ui.item = it;
  $('#item-title').textContent = itemTitle(it);
  const badge = $('#item-status');
  badge.className = 'badge ' + it.status;
  badge.textContent = STATUS_NAMES[it.status] || it.status;
  $('#f-title').value = it.title || '';
  $('#f-sku').value = it.sku || '';
  $('#f-price').value = priceText(it.price_cents);
  $('#f-tags').value = (it.tags || []).join(', ');
  $('#f-notes').value = it.notes || '';
  $('#f-title').placeholder = it.default_title || '';
  const a = it.attributes || {};
  $('#f-type').value = it.type || 'top';
  $('#f-color').value = a.color || '';
  $('#f-sleeve').value = a.sleeve || '';
  $('#f-skirt').value = a.skirt || '';
  $('#f-print').checked = a.pattern === 'print';
  $('#f-sleeve-field').hidden = !(it.type === 'top' || it.type === 'dress');
  $('#f-skirt-field').hidden = !(it.type === 'skirt' || it.type === 'dress');
  loadTape(it);
  $('#f-approve').hidden = it.status === 'approved';
  $('#f-reject').hidden = it.status === 'rejected';
  const note = reviewNote(it);
  $('#item-review').hidden = !note;
  $('#item-review').classList.toggle('rejected', !!(note && note.rejected));
  $('#item-review-title').textContent = note ? note.title : '';
  $('#item-review-detail').textContent = note ? note.detail : '';
  $('#f-msg').textContent = '';
  $('#item-meta').textContent = [TYPE_NAMES[it.type] || it.type,
    ...Object.entries(it.attributes || {}).map(([k, v]) => k + ': ' + v),
    it.confidence ? 'confidence ' + Math.round(it.confidence * 100) + '%' : null,
    it.base_size ? 'fits size ' + it.base_size : null,
    (it.attributes || {}).color ? 'colour ' + it.attributes.color : null,
    'captured ' + (it.created_at || '').replace('T', ' ').replace('Z', ' UTC')].filter(Boolean).join(' · ');
  showWarnings($('#item-warn'), $('#item-notes'), it.warnings, it.checks);
  // Photos
  const kinds = ['product', 'product_ghost', 'product_back', 'cutout', 'dressed', 'back', 'overlay', 'texture']
    .filter((k) => it.images && it.images[k]);
  ui.photoKind = kinds[0] || null;
  $('#thumbs').replaceChildren(...kinds.map((k) => el('button', {
    type: 'button', class: k === ui.photoKind ? 'on' : '', onclick: () => { ui.photoKind = k; showPhoto(); },
  }, el('img', { src: it.images[k].url, alt: k }), k)));
  showPhoto();
  // Sizes
  const sizes = it.sizes && it.sizes.length ? it.sizes : [];
  const sel = $('#size-select');
  sel.replaceChildren(...sizes.map((s) => el('option', { value: s, text: s === 'base' ? 'as measured' + (it.base_size ? ' (' + it.base_size + ')' : '') : s })));
  ui.itemSize = sizes.includes(ui.itemSize) ? ui.itemSize : (sizes[0] || 'base');
  sel.value = ui.itemSize;
  showPattern();
  loadSizeGuide(it);
  await loadMeasurementEditor(it);
  setItemFormLoading(false);
}
function showPhoto() {
  const it = ui.item;
  $$('#thumbs button').forEach((b) => b.classList.toggle('on', b.textContent === ui.photoKind));
  $('#photos').replaceChildren(ui.photoKind ? el('img', { src: it.images[ui.photoKind].url, alt: ui.photoKind + ' photo' })
    : el('span', { class: 'muted', text: 'No photos' }));
}
function showPattern() {
  const it = ui.item;
  const size = ui.itemSize;
  const base = '/api/items/' + it.id;
  const q = '?size=' + encodeURIComponent(size);
  if (!it.sizes || !it.sizes.length) {
    // A failed draft stores no pattern; the item's warning says why ("no pattern: <reason>").
    const why = (it.warnings || []).find((w) => w.startsWith('no pattern: '));
    $('#panels').replaceChildren(el('span', { class: 'muted', text: why ? 'No pattern for this item: ' + why.slice(12) : 'No pattern for this item' }));
    $('#pattern-links').replaceChildren();
    return;
  }
  const img = el('img', { src: base + '/pattern.svg' + q, alt: 'Pattern panels, size ' + size });
  img.onerror = () => $('#panels').replaceChildren(el('span', { class: 'muted', text: 'The pattern cannot be drawn in this build.' }));
  $('#panels').replaceChildren(img);
  const links = [
    ['DXF-AAMA', '/pattern.dxf' + q], ['PDF A4 tiled', '/pattern.pdf' + q],
    ['PDF Letter tiled', '/pattern.pdf' + q + '&paper=letter'], ['PDF A0', '/pattern.pdf' + q + '&paper=a0'],
    ['SVG 1:1', '/pattern.svg' + q], ['GarmentCode', '/garmentcode.json' + q], ['Valentina .vit', '/measurements.vit'],
    // This size's pieces laid on 150 cm fabric (the API takes other widths and several sizes).
    ['Marker 150 cm PDF', '/marker.pdf?sizes=' + encodeURIComponent(size)],
  ];
  if (it.sizes.filter((s) => s !== 'base').length >= 2)
    links.push(['Graded DXF', '/pattern_graded.dxf'], ['Grade rules .RUL', '/pattern_graded.rul'],
      ['Nested grading SVG', '/nested_grading.svg'], ['Nested grading PDF', '/nested_grading.pdf'],
      ['Nested grading DXF', '/nested_grading.dxf']);
  $('#pattern-links').replaceChildren(...links.map(([t, p]) =>
    el('a', { class: 'btn small secondary', href: base + p, download: '', text: t, onclick: download })));
}
async function loadSizeGuide(it) {
  let g = null;
  try { g = await api('GET', '/api/items/' + it.id + '/sizeguide.json'); } catch (e) { g = null; }
  $('#sizeguide').replaceChildren(...sizeGuideView(g, it.measurements));
}

// Measurements as inputs; the value measured by the station (result.json) is shown beside a
// corrected one, and stays in result.json for the record, with how far it may be off
// (result.json's uncertainty_cm, 95 %), so staff know which readings to check with a tape.
async function loadMeasurementEditor(it) {
  const box = $('#f-meas');
  let measured = {};
  let uncertainty = {};
  let corrections = {};
  try {
    const r = (await api('GET', '/api/items/' + it.id + '/result.json')) || {};
    measured = r.measurements || {};
    uncertainty = r.uncertainty_cm || {};
    corrections = r.corrections || {};
  } catch (e) { measured = {}; }
  const m = it.measurements || {};
  box.replaceChildren(...sortedMeas(Object.assign({}, measured, m)).map((n) => {
    const orig = measured[n];
    const now = m[n];
    const changed = orig != null && now != null && Math.abs(orig - now) >= 0.05;
    const pm = uncertainty[n] != null ? ' \u00b1' + cm(uncertainty[n]) + ' cm' : '';
    return el('label', { class: 'meas-row' + (changed ? ' changed' : '') },
      el('span', { text: measName(n) }),
      el('input', { 'data-name': n, inputmode: 'decimal', value: now == null ? '' : cm(now), 'aria-label': measName(n) + ' in cm' }),
      el('small', { class: 'muted', text: orig == null ? '' : (changed ? 'measured ' + cm(orig) + pm
        : corrections[n] ? 'tape-corrected from ' + cm(corrections[n].raw_cm) : 'as measured' + pm) }));
  }));
}
// The shop's tape measure (POST /api/tape): one input per measurement the capture made, filled
// with what was taped before. The corrections panel lists every type's fit with its
// leave-one-out residual: the error a new garment can expect after correction.
async function loadTape(it) {
  const box = $('#tape-meas');
  let data = { tape: [], corrections: [] };
  try { data = await api('GET', '/api/tape'); } catch (e) { $('#tape-msg').textContent = e.message; }
  const mine = {};
  for (const row of data.tape) if (row.item === it.id) mine[row.measurement] = row;
  const names = sortedMeas(it.measurements || {});
  box.replaceChildren(...names.map((n) => el('label', { class: 'meas-row' },
    el('span', { text: measName(n) }),
    el('input', { 'data-name': n, inputmode: 'decimal', value: mine[n] ? cm(mine[n].tape_cm) : '', placeholder: cm(it.measurements[n]), 'aria-label': measName(n) + ' taped, cm' }),
    el('small', { class: 'muted', text: mine[n] ? 'station read ' + cm(mine[n].measured_cm) : '' }))));
  $('#tape-form').hidden = !it.type || !names.length;
  $('#tape-clear').hidden = !Object.keys(mine).length;
  $('#tape-msg').textContent = '';
  renderCorrections(data.corrections, it.type);
}
function renderCorrections(rows, type) {
  const box = $('#corrections');
  if (!rows || !rows.length) { box.replaceChildren(el('span', { class: 'muted', text: 'Nothing taped yet.' })); return; }
  const fmt = (r) => r.kind === 'none' ? (r.reason ? 'none: it would not help' : 'none yet (' + r.needs + ' more)')
    : (r.kind === 'scale_offset' ? '\u00d7' + r.scale.toFixed(3) + ' ' : '') + (r.offset_cm >= 0 ? '+' : '') + cm(r.offset_cm) + ' cm';
  box.replaceChildren(el('table', { class: 'guide' },
    el('thead', {}, el('tr', {}, ...['Type', 'Measurement', 'n', 'Correction', 'Left-out error'].map((t) => el('th', { text: t })))),
    el('tbody', {}, ...rows.map((r) => el('tr', { class: r.type === type ? 'base' : '' },
      el('td', { text: TYPE_NAMES[r.type] || r.type }), el('td', { text: measName(r.measurement) }),
      el('td', { text: String(r.n) }), el('td', { text: fmt(r) }),
      el('td', { text: r.kind === 'none' && !r.reason ? '\u2013' : cm(r.residual_cm) + ' cm (was ' + cm(r.raw_error_cm) + ')' }))))));
}
async function saveTape(ev) {
  ev.preventDefault();
  const it = ui.item;
  const measurements = {};
  for (const input of $$('#tape-meas input')) {
    const v = input.value.trim().replace(',', '.');
    if (v === '') continue;
    if (!/^\d+(\.\d+)?$/.test(v) || !(parseFloat(v) > 0 && parseFloat(v) <= 400)) {
      toast(measName(input.dataset.name) + ': a length in cm like 72.5', true);
      input.focus();
      return;
    }
    measurements[input.dataset.name] = parseFloat(v);
  }
  if (!Object.keys(measurements).length) { toast('Type at least one taped measurement.', true); return; }
  try {
    await api('POST', '/api/tape', { item: it.id, measurements });
    toast('Tape measurements saved: they correct the next captures');
    loadTape(it);
  } catch (e) { toast(e.message, true); }
}
async function clearTape() {
  try { await api('DELETE', '/api/tape/' + ui.item.id); toast('Tape measurements removed'); loadTape(ui.item); } catch (e) { toast(e.message, true); }
}
function attributePatch(it) {
  const a = Object.assign({}, it.attributes || {});
  const set = (k, v) => { if (v) a[k] = v; else delete a[k]; };
  set('color', $('#f-color').value.trim());
  if (!$('#f-sleeve-field').hidden) set('sleeve', $('#f-sleeve').value);
  if (!$('#f-skirt-field').hidden) set('skirt', $('#f-skirt').value);
  a.pattern = $('#f-print').checked ? 'print' : 'solid';
  return JSON.stringify(a) === JSON.stringify(it.attributes || {}) ? null : a;
}
async function setStatus(status, done) {
  try { await api('PATCH', '/api/items/' + ui.item.id, { status }); toast(done); loadItem(ui.item.id); } catch (e) { toast(e.message, true); }
}
async function saveItem(ev) {
  ev.preventDefault();
  const it = ui.item;
  const body = {
    title: $('#f-title').value.trim(),
    notes: $('#f-notes').value,
    tags: $('#f-tags').value.split(',').map((t) => t.trim()).filter(Boolean),
  };
  if ($('#f-type').value !== it.type) body.type = $('#f-type').value;
  const attrs = attributePatch(it);
  if (attrs) body.attributes = attrs;
  const meas = {};
  for (const input of $$('#f-meas input')) {
    const v = input.value.trim().replace(',', '.');
    if (v === '') continue;
    if (!/^\d+(\.\d+)?$/.test(v) || !(parseFloat(v) > 0 && parseFloat(v) < 1000)) {
      toast(measName(input.dataset.name) + ': a length in cm like 72.5', true);
      input.focus();
      return;
    }
    const old = (it.measurements || {})[input.dataset.name];
    if (old == null || Math.abs(old - parseFloat(v)) >= 0.05) meas[input.dataset.name] = parseFloat(v);
  }
  if (Object.keys(meas).length) body.measurements = meas;
  const sku = $('#f-sku').value.trim();
  if (sku !== (it.sku || '')) {
    if (sku && !/^[A-Za-z0-9._-]{1,64}$/.test(sku)) { toast('A SKU may hold only letters, digits, dot, dash and underscore.', true); return; }
    body.sku = sku;
  }
  const price = parsePrice($('#f-price').value);
  if (price === undefined) { toast('Price: a number like 49.90', true); return; }
  body.price_cents = price;
  try {
    await api('PATCH', '/api/items/' + it.id, body);
    $('#f-msg').textContent = 'Saved ✓';
    toast('Saved');
    loadItem(it.id);
  } catch (e) { toast(e.message, true); }
}

// --- export ---------------------------------------------------------------------------------
// The shop's settings live on the station (PUT /api/settings/shop), so every export and every
// browser uses the same brand and links; the legacy Shopify columns are a per-download choice.
const SHOP_TEXT = ['public_base_url', 'store_url', 'brand', 'currency'];
const SHOP_NAMES = { brand: 'the brand', store_url: 'the shop URL', public_base_url: 'the public image URL' };
function showShopSettings(r) {
  const s = r.settings || {};
  for (const k of SHOP_TEXT) $('#s-' + k).value = s[k] || '';
  $('#s-store_platform').value = s.store_platform || 'shopify';
  $('#s-made_to_order').checked = !!s.made_to_order;
  const missing = (r.missing || []).map((k) => SHOP_NAMES[k] || k);
  $('#s-missing').hidden = missing.length === 0;
  $('#s-missing').textContent = missing.length
    ? 'Set up your shop first: ' + missing.join(', ') + (missing.length === 1 ? ' is' : ' are') + ' missing, so the exports cannot link to your shop.'
    : '';
}
async function loadShopSettings() {
  try { showShopSettings(await api('GET', '/api/settings/shop')); } catch (e) { toast(e.message, true); }
}
async function saveShopSettings(ev) {
  ev.preventDefault();
  const body = {};
  for (const k of SHOP_TEXT) body[k] = $('#s-' + k).value.trim();
  body.currency = (body.currency || 'EUR').toUpperCase();
  body.store_platform = $('#s-store_platform').value;
  body.made_to_order = $('#s-made_to_order').checked;
  try {
    showShopSettings(await api('PUT', '/api/settings/shop', body));
    toast('Shop settings saved');
  } catch (e) {
    const key = (/shop\.(\w+)/.exec(e.message) || [])[1];
    if (key && $('#s-' + key)) $('#s-' + key).focus();
    toast('Not saved: ' + e.message.replace(/^shop\./, ''), true);
  }
}
function updateExportLinks() {
  $('#x-shopify').href = '/api/export/shopify.csv' + ($('#s-legacy').checked ? '?legacy=1' : '');
  $('#x-woo').href = '/api/export/woocommerce.csv';
  $('#x-merchant').href = '/api/export/merchant.tsv';
  $('#x-zip').href = '/api/export/catalog.zip';
}
async function loadExportCounts() {
  try {
    const [a, r] = await Promise.all([api('GET', '/api/items?status=approved&limit=1'), api('GET', '/api/items?status=needs_review&limit=1')]);
    $('#export-count').textContent = a.total + ' approved item' + (a.total === 1 ? '' : 's') + ' will be exported' +
      (r.total ? '; ' + r.total + ' waiting for review are left out until approved.' : '.');
  } catch (e) { $('#export-count').textContent = e.message; }
}
// Downloads through fetch (common.js): a busy station lays one marker at a time.
function download(ev) {
  ev.preventDefault();
  downloadFile(ev.currentTarget.href, 'The station is busy with another marker');
}

// --- routing --------------------------------------------------------------------------------
function currentView() { return (location.hash.match(/^#\/(\w+)/) || [])[1] || 'capture'; }
function route() {
  const view = currentView();
  $$('.view').forEach((v) => { v.hidden = v.dataset.view !== view; });
  $$('.tabs a').forEach((a) => a.classList.toggle('on', a.dataset.tab === view || (view === 'item' && a.dataset.tab === 'catalog')));
  const preview = $('#preview');
  if (view === 'capture') {
    if (!preview.getAttribute('src')) preview.src = '/stream.mjpg';
  } else if (preview.getAttribute('src')) {
    preview.removeAttribute('src');  // closes the MJPEG stream while it is not seen
  }
  if (view === 'catalog') loadCatalog(true);
  if (view === 'item') loadItem((location.hash.match(/^#\/item\/(\d+)/) || [])[1]);
  if (view === 'export') { updateExportLinks(); loadExportCounts(); loadShopSettings(); }
}

// The preview box takes the camera frame's aspect (app.css, --preview-aspect), so a portrait
// camera fills it instead of sitting between black bars.
function fitPreview() {
  const img = $('#preview');
  if (img.naturalWidth > 0 && img.naturalHeight > 0) {
    $('.capture-grid').style.setProperty('--preview-aspect', (img.naturalWidth / img.naturalHeight).toFixed(4));
  }
}

function init() {
  $('#btn-capture').addEventListener('click', captureGarment);
  $('#btn-empty').addEventListener('click', captureEmpty);
  // A USB barcode scanner types the SKU and Enter: that is a capture.
  $('#sku').addEventListener('keydown', (e) => { if (e.key === 'Enter') { e.preventDefault(); if (!$('#btn-capture').disabled) captureGarment(); } });
  $('#preview').addEventListener('error', () => { $('#preview-off').hidden = false; $('#preview').style.visibility = 'hidden'; setTimeout(() => { if (currentView() === 'capture') { $('#preview').src = '/stream.mjpg?t=' + Date.now(); } }, 3000); });
  $('#preview').addEventListener('load', () => { $('#preview-off').hidden = true; $('#preview').style.visibility = ''; fitPreview(); });
  $('#search').addEventListener('input', () => {
    clearTimeout(searchTimer);
    searchTimer = setTimeout(() => { ui.catalog.q = $('#search').value.trim(); loadCatalog(true); }, 250);
  });
  $$('#type-filter .chip').forEach((b) => b.addEventListener('click', () => {
    $$('#type-filter .chip').forEach((x) => x.classList.toggle('on', x === b));
    ui.catalog.type = b.dataset.type;
    loadCatalog(true);
  }));
  $('#status-filter').addEventListener('change', (e) => { ui.catalog.status = e.target.value; loadCatalog(true); });
  $('#more').addEventListener('click', () => loadCatalog(false));
  $('#item-form').addEventListener('submit', saveItem);
  $('#tape-form').addEventListener('submit', saveTape);
  $('#tape-clear').addEventListener('click', clearTape);
  $('#f-approve').addEventListener('click', () => setStatus('approved', 'Approved'));
  $('#f-reject').addEventListener('click', () => setStatus('rejected', 'Rejected: it will not be exported'));
  $('#bulk-approve').addEventListener('click', approvePicked);
  $('#colour-names').replaceChildren(...COLOUR_NAMES.map((c) => el('option', { value: c })));
  $('#size-select').addEventListener('change', (e) => { ui.itemSize = e.target.value; showPattern(); });
  $('#btn-rerun').addEventListener('click', async () => {
    try {
      const r = await api('POST', '/api/items/' + ui.item.id + '/rerun');
      applyJob({ id: r.job, state: 'queued', kind: 'rerun', progress: 0 });
      toast('Re-run queued (job ' + r.job + ')');
    } catch (e) { toast(e.message, true); }
  });
  $('#btn-back').addEventListener('click', async () => {
    try {
      const r = await api('POST', '/api/items/' + ui.item.id + '/back');
      applyJob({ id: r.job, state: 'queued', kind: 'back', progress: 0 });
      toast('Back shot queued (job ' + r.job + ')');
    } catch (e) { toast(e.message, true); }
  });
  $('#btn-delete').addEventListener('click', async () => {
    if (!confirm('Delete "' + itemTitle(ui.item) + '"? It can be restored from the API.')) return;
    try { await api('DELETE', '/api/items/' + ui.item.id); toast('Deleted'); location.hash = '#/catalog'; } catch (e) { toast(e.message, true); }
  });
  $('#s-legacy').addEventListener('change', updateExportLinks);
  $('#export-settings').addEventListener('submit', saveShopSettings);
  $$('.export-buttons a').forEach((a) => a.addEventListener('click', download));
  window.addEventListener('hashchange', route);
  route();
  refreshStatus();
  connectEvents();
}

document.addEventListener('DOMContentLoaded', init);
