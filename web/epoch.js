// One epoch (/epochs/N): its status, registration with every target's residual and test,
// the meteo used, the stages' times, and the M3C2 map of every zone: core points in the
// zone's wall frame coloured by distance (diverging scale, legend in mm), points whose
// distance is within their LoD95 greyed, distance, LoD, n1 and n2 on hover.
import { element, formatTime, getJson, header, showError } from './common.js';

const id = Number(location.pathname.split('/').pop());

function row(label, value) {
  return element('tr', {}, element('th', { text: label }), element('td', { text: value }));
}
const mm = (m, digits = 2) => (m === null || m === undefined ? '—' : `${(m * 1000).toFixed(digits)} mm`);

// Blue (towards the scanner: negative) – white – red, symmetric about zero.
function diverging(t) {
  const c = Math.max(-1, Math.min(1, t));
  const a = Math.abs(c);
  const [r, g, b] = c < 0 ? [255 - a * 222, 255 - a * 160, 255 - a * 40] : [255 - a * 40, 255 - a * 200, 255 - a * 210];
  return `rgb(${r | 0},${g | 0},${b | 0})`;
}

function legend(limit) {
  const bar = element('canvas', { width: 160, height: 12 });
  const ctx = bar.getContext('2d');
  for (let x = 0; x < 160; ++x) {
    ctx.fillStyle = diverging((x / 159) * 2 - 1);
    ctx.fillRect(x, 0, 1, 12);
  }
  return element('div', { class: 'map-legend' },
    element('span', { text: `−${(limit * 1000).toFixed(1)} mm` }), bar,
    element('span', { text: `+${(limit * 1000).toFixed(1)} mm` }),
    element('span', { class: 'quiet', text: ' grey: within LoD95' }));
}

// The zone's core points to scale (one metre is as long across as up), at most 480 × 420 px.
function drawZone(z, limit) {
  const n = z.u.length, pad = 12;
  const title = element('h3', { text: `${z.zone}: ${n} of ${z.core_points} core points with a distance` });
  if (n === 0) return element('div', {}, title);
  const u0 = Math.min(...z.u), u1 = Math.max(...z.u), v0 = Math.min(...z.v), v1 = Math.max(...z.v);
  const scale = Math.min((480 - 2 * pad) / Math.max(u1 - u0, 1e-3), (420 - 2 * pad) / Math.max(v1 - v0, 1e-3));
  const w = Math.max(160, Math.ceil((u1 - u0) * scale + 2 * pad)), h = Math.ceil((v1 - v0) * scale + 2 * pad);
  const canvas = element('canvas', { class: 'map', width: w, height: h });
  const box = element('div', {}, title, canvas,
    element('p', { class: 'quiet', text: z.frame === 'wall' ? `wall frame: ${(u1 - u0).toFixed(1)} m along, ${(v1 - v0).toFixed(1)} m up` : `plan: ${(u1 - u0).toFixed(1)} m × ${(v1 - v0).toFixed(1)} m` }));
  const px = (i) => pad + (z.u[i] - u0) * scale;
  const py = (i) => h - pad - (z.v[i] - v0) * scale;
  const r = Math.max(1.5, Math.min(5, scale * Math.sqrt(((u1 - u0) * (v1 - v0)) / n) * 0.45));
  const ctx = canvas.getContext('2d');
  for (let i = 0; i < n; ++i) {
    ctx.fillStyle = z.significant[i] ? diverging(z.distance_m[i] / limit) : '#c4c4c4';
    ctx.beginPath();
    ctx.arc(px(i), py(i), r, 0, 2 * Math.PI);
    ctx.fill();
  }
  const tip = document.querySelector('#map-tip');
  canvas.addEventListener('mousemove', (ev) => {
    const rect = canvas.getBoundingClientRect();
    const x = ev.clientX - rect.left, y = ev.clientY - rect.top;
    let best = -1, bestD = (r + 3) ** 2;
    for (let i = 0; i < n; ++i) {
      const d = (px(i) - x) ** 2 + (py(i) - y) ** 2;
      if (d < bestD) { best = i; bestD = d; }
    }
    if (best < 0) { tip.style.display = 'none'; return; }
    tip.textContent = `core ${z.core[best]}: d = ${mm(z.distance_m[best])}, LoD95 = ${mm(z.lod95_m[best])}, n1 = ${z.n1[best]}, n2 = ${z.n2[best]}${z.significant[best] ? ' (significant)' : ''}`;
    tip.style.left = `${ev.clientX + 12}px`;
    tip.style.top = `${ev.clientY + 12}px`;
    tip.style.display = 'block';
  });
  canvas.addEventListener('mouseleave', () => { tip.style.display = 'none'; });
  canvas.dataset.marks = String(n);
  return box;
}

async function maps() {
  const box = document.querySelector('#maps');
  try {
    const map = await getJson(`/api/v1/epochs/${id}/corepoints`);
    window.tlsmonMap = map;  // what the maps draw, for scripts and tests
    const all = map.zones.flatMap((z) => z.distance_m.map(Math.abs)).sort((a, b) => a - b);
    // The scale's end: the 98th percentile of |d|, so one outlier does not wash out the rest.
    const limit = Math.max(all.length ? all[Math.floor(0.98 * (all.length - 1))] : 0, 0.0005);
    document.querySelector('#map-legend').replaceChildren(legend(limit));
    box.replaceChildren(...map.zones.map((z) => drawZone(z, limit)));
  } catch (e) {
    box.replaceChildren(element('p', { class: 'quiet', text: String(e.message) }));
  }
}

async function start() {
  try {
    const [site, e] = await Promise.all([getJson('/api/v1/site'), getJson(`/api/v1/epochs/${id}`)]);
    window.tlsmonEpoch = e;
    header(site.station, '');
    document.title = `tlsmon — epoch ${id}`;
    document.querySelector('#title').textContent = `Epoch #${id}, ${formatTime(e.acquired)}`;
    const links = [element('a', { href: `/epochs/${id - 1}`, text: '← previous' }),
      element('a', { href: `/epochs/${id + 1}`, text: 'next →' })];
    const compare = element('form', {}, element('label', { text: 'compare with epoch ' }),
      element('input', { name: 'k', size: 5 }), element('button', { type: 'submit', text: 'open' }));
    compare.addEventListener('submit', (ev) => {
      ev.preventDefault();
      const k = Number(compare.elements.k.value);
      if (k > 0) window.open(`/epochs/${k}`, '_blank');
    });
    document.querySelector('#links').replaceChildren(...links, compare);
    document.querySelector('#summary').replaceChildren(element('table', {},
      row('Status', e.status), row('Reason', e.reason || '—'), row('File', e.archived_as || e.file),
      row('Points', e.points ?? '—'),
      row('Processing', e.total_ms === null ? '—' : `${(e.total_ms / 1000).toFixed(2)} s`)));
    const g = e.registration;
    document.querySelector('#registration').replaceChildren(g ? element('table', {},
      row('Method', g.method), row('Verdict', g.accepted ? 'accepted' : `not accepted (${g.status})`),
      row('Reason', g.reason || '—'), row('Targets', `${g.targets_used} used, ${g.targets_left_out} left out`),
      row('s0', g.sigma0 === null ? '—' : g.sigma0.toFixed(2)), row('RMS', mm(g.rms_m)),
      ...g.sigma_at_zones.map((s) => row(`σ at ${s.zone}`, mm(s.sigma_3d_m)))) : element('p', { text: 'none stored' }));
    const m = e.meteo;
    document.querySelector('#meteo').replaceChildren(m ? element('table', {},
      row('Row time', formatTime(m.time)), row('Air temperature', `${m.air_temperature_c.toFixed(1)} °C`),
      row('Pressure', `${m.pressure_hpa.toFixed(1)} hPa`), row('Humidity', `${m.relative_humidity_pct.toFixed(0)} %`))
      : element('p', { class: 'quiet', text: 'no meteo file with this epoch' }));
    const targets = element('table', { class: 'list' }, element('tr', {},
      ...['Target', 'Kind', 'Status', 'Use', 'Residual x, y, z', 'Test', 'Stable'].map((h) => element('th', { text: h }))));
    for (const t of e.targets) {
      targets.append(element('tr', {},
        element('td', { text: t.target }), element('td', { text: t.kind }),
        element('td', { text: t.status + (t.reason ? ` (${t.reason})` : '') }), element('td', { text: t.use }),
        element('td', { text: t.residual_m.map((r) => (r * 1000).toFixed(2)).join(', ') + ' mm' }),
        element('td', { text: t.statistic === null ? '—' : `${t.statistic.toFixed(2)} / ${t.critical.toFixed(2)}` }),
        element('td', { text: t.stable ? 'yes' : 'no' })));
    }
    document.querySelector('#targets').replaceChildren(e.targets.length ? targets : element('p', { class: 'quiet', text: 'no target observed' }));
    const stages = element('table', { class: 'list' }, element('tr', {},
      ...['Stage', 'Time', 'Rejected', 'Note'].map((h) => element('th', { text: h }))));
    for (const s of e.stages) {
      stages.append(element('tr', {}, element('td', { text: s.stage }), element('td', { text: `${s.ms.toFixed(0)} ms` }),
        element('td', { text: s.rejected || '' }), element('td', { text: s.note })));
    }
    document.querySelector('#stages').replaceChildren(stages);
    await maps();
  } catch (err) {
    showError('#summary', err);
  }
}

start();
