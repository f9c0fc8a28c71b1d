// Calibration (/calibration): whether each method's σ / LoD95 covered its error at the nominal
// rate over a window back from the newest epoch (docs/calibration.md), as
// GET /api/v1/calibration computes it from the site's own checks.
import { buttons, element, formatTime, getJson, header, onEpochCommitted, showError } from './common.js';

const windows = [['7 days', 7 * 86400], ['30 days', 30 * 86400], ['1 year', 365 * 86400], ['all', 0]];
const params = new URLSearchParams(location.search);
let span = Number(params.get('window') ?? 30 * 86400);

// A length (m) in mm, an angle (rad) in µrad; blank where a row has shares only.
function number(row, v) {
  if (v === null || row.unit === null) return '';
  return row.unit === 'rad' ? (v * 1e6).toFixed(1) : (v * 1e3).toFixed(3);
}

function share(row, within, band, verdict) {
  const pct = row.n ? (100 * within) / row.n : 0;
  return [
    element('td', { class: 'value', text: `${pct.toFixed(1)} %`, 'data-within': String(within) }),
    element('td', { class: 'quiet', text: `${(100 * band[0]).toFixed(1)}–${(100 * band[1]).toFixed(1)} %` }),
    element('td', { class: `verdict verdict-${verdict.replaceAll(' ', '-')}`, text: verdict }),
  ];
}

function table(rows) {
  const head = ['Method', 'Part', 'n', 'Unit', 'Bias', 'RMS', 'Max |e|', 'RMS σ',
    'Within σ', '95 % band', 'Verdict (68 %)', 'Within 1.96 σ', '95 % band', 'Verdict (95 %)'];
  const t = element('table', { class: 'list calibration' },
    element('tr', {}, ...head.map((h) => element('th', { text: h }))));
  for (const r of rows) {
    t.append(element('tr', { class: r.part === 'all' ? 'pooled' : '', 'data-method': r.method, 'data-part': r.part },
      element('td', { text: r.method }),
      element('td', { text: r.part }),
      element('td', { class: 'value', text: String(r.n) }),
      element('td', { text: r.unit === null ? '' : r.unit === 'rad' ? 'µrad' : 'mm' }),
      element('td', { class: 'value', text: number(r, r.bias) }),
      element('td', { class: 'value', text: number(r, r.rms) }),
      element('td', { class: 'value', text: number(r, r.max_abs) }),
      element('td', { class: 'value', text: number(r, r.rms_sigma) }),
      ...share(r, r.within68, r.band68, r.verdict68),
      ...share(r, r.within95, r.band95, r.verdict95)));
  }
  return t;
}

async function load() {
  try {
    const site = await getJson('/api/v1/site');
    header(site.station, '/calibration');
    buttons('#windows', windows, (s) => s === span, (s) => {
      span = s;
      history.replaceState(null, '', `/calibration?window=${s}`);  // a view that can be sent on
      load();
    });
    const q = new URLSearchParams();
    if (span > 0 && site.last_epoch) q.set('from', String(site.last_epoch.t - span));
    const c = await getJson(`/api/v1/calibration?${q}`);
    window.tlsmonCalibration = c;  // what the table shows, for scripts and tests
    document.querySelector('#window-note').textContent =
      `${c.epochs} epoch(s) from ${c.from ? formatTime(c.from) : 'the first'} to ${c.to ? formatTime(c.to) : 'the newest'}`;
    document.querySelector('#calibration').replaceChildren(c.rows.length
      ? table(c.rows)
      : element('p', { class: 'quiet', text: 'Nothing to check in this window: no check zone ([[zone]] no_change = true) with a value, no epoch registered on four targets or more, no joined registration estimates.' }));
  } catch (e) {
    showError('#calibration', e);
  }
}

load();
onEpochCommitted(load);
