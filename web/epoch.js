// One epoch (/epochs/N): its status, registration with every target's residual and test,
// the meteo used, the stages' times, and the M3C2 map of every zone: core points in the
// zone's wall frame coloured by distance (diverging scale, legend in mm), points whose
// distance is within their LoD95 greyed, distance, LoD, n1 and n2 on hover; and where the
// keypoint method measured the zone, its mean vector along the wall as an arrow at the
// segment's height (black: beyond its LoD95, grey: within), its LoD95 as an ellipse at the
// tip, all arrows to one scale with a scale bar; where the 3-D vectors stage measured, every
// area's vector along the wall as a thin arrow from its centre, to a scale of their own.
import { element, formatTime, getJson, header, showError } from './common.js';
import { colourBar, roundLength, scaleBar } from './map_legend.js';

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
  return colourBar((t) => diverging(t * 2 - 1), `−${(limit * 1000).toFixed(1)} mm`,
    `+${(limit * 1000).toFixed(1)} mm`, ' grey: within LoD95');
}

// The arrows' scale: a round length drawn about 60 px long.
function arrowLegend(pxPerMetre, label, note) {
  const length = roundLength(60 / pxPerMetre);
  return scaleBar(length * pxPerMetre, label, `${Number((length * 1000).toPrecision(2))} mm`, note);
}

// An arrow from (x, y) to (tx, ty).
function arrow(ctx, x, y, tx, ty, colour, width, headMax) {
  ctx.strokeStyle = colour;
  ctx.fillStyle = colour;
  ctx.lineWidth = width;
  ctx.beginPath();
  ctx.moveTo(x, y);
  ctx.lineTo(tx, ty);
  ctx.stroke();
  const angle = Math.atan2(ty - y, tx - x), head = Math.min(headMax, Math.hypot(tx - x, ty - y) * 0.5);
  ctx.beginPath();
  ctx.moveTo(tx, ty);
  ctx.lineTo(tx - head * Math.cos(angle - 0.4), ty - head * Math.sin(angle - 0.4));
  ctx.lineTo(tx - head * Math.cos(angle + 0.4), ty - head * Math.sin(angle + 0.4));
  ctx.fill();
}

// The zone's keypoint vector: an arrow from (x, y) by (du, dv) at `k` px per metre.
function drawArrow(ctx, x, y, kp, k) {
  const tx = x + kp.du_m * k, ty = y - kp.dv_m * k;
  ctx.save();
  arrow(ctx, x, y, tx, ty, kp.significant ? '#000' : '#8a8a8a', 2, 8);
  if (kp.lod95_h_m !== null && kp.lod95_v_m !== null) {
    ctx.lineWidth = 1;
    ctx.setLineDash([3, 2]);
    ctx.beginPath();
    ctx.ellipse(tx, ty, Math.max(1, kp.lod95_h_m * k), Math.max(1, kp.lod95_v_m * k), 0, 0, 2 * Math.PI);
    ctx.stroke();
  }
  ctx.restore();
}

// Whether an area's vector is beyond its LoD95 along the wall (either axis).
const areaSignificant = (a, i) => Math.abs(a.du_m[i]) > a.lod95_u_m[i] || Math.abs(a.dv_m[i]) > a.lod95_v_m[i];

// The zone's core points to scale (one metre is as long across as up), at most 480 × 420 px.
function drawZone(z, limit, arrowScale, areaScale) {
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
  canvas.dataset.arrows = '0';
  canvas.dataset.areaArrows = '0';
  const a = z.vectors;
  if (a && a.u.length) {
    // Every area's 3-D vector along the wall from its centre (dark blue: beyond its LoD95
    // along u or v; grey: within), under the zone's keypoint arrow.
    ctx.save();
    for (let i = 0; i < a.u.length; ++i) {
      const x = pad + (a.u[i] - u0) * scale, y = h - pad - (a.v[i] - v0) * scale;
      // An arrow longer than three times the typical one (an area across a step, which is no
      // rigid body) is drawn at that length, so it does not cross the whole map.
      const len = Math.hypot(a.du_m[i], a.dv_m[i]) * areaScale, cut = len > 75 ? 75 / len : 1;
      const tx = x + a.du_m[i] * areaScale * cut, ty = y - a.dv_m[i] * areaScale * cut;
      arrow(ctx, x, y, tx, ty, 'rgba(255,255,255,0.8)', 3, 5);  // a halo over the map's colours
      arrow(ctx, x, y, tx, ty, areaSignificant(a, i) ? '#0b3d91' : '#6e6e6e', 1.2, 4);
    }
    ctx.restore();
    canvas.dataset.areaArrows = String(a.u.length);
    const beyond = a.u.filter((_, i) => areaSignificant(a, i)).length;
    const mean = (xs) => xs.reduce((p, q) => p + q, 0) / xs.length;
    box.append(element('p', { class: 'quiet', text:
      `3-D vectors: ${a.u.length} areas, ${beyond} beyond their LoD95 along the wall; mean along the wall ` +
      `${mm(mean(a.du_m))}, up ${mm(mean(a.dv_m))}, along the normal ${mm(mean(a.dw_m))}` }));
  }
  const kp = z.keypoint;
  if (kp) {
    // At the middle of the zone along the wall, at the segment's height (wall frame).
    const uMid = (u0 + u1) / 2;
    const vAt = z.frame === 'wall' && kp.height_m !== null ? kp.height_m : (v0 + v1) / 2;
    drawArrow(ctx, pad + (uMid - u0) * scale, h - pad - (vAt - v0) * scale, kp, arrowScale);
    canvas.dataset.arrows = '1';
    box.append(element('p', { class: 'quiet', text:
      `keypoints: ${kp.kept} matches kept; along the wall ${mm(kp.du_m)}, up ${mm(kp.dv_m)}` +
      ` (LoD95 ${mm(kp.lod95_h_m)} horizontal, ${mm(kp.lod95_v_m)} vertical)` +
      (kp.significant ? '' : ', within the LoD95') }));
  }
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
    // One scale for every arrow: the longest vector or LoD95 ellipse 60 px.
    const reach = Math.max(1e-5, ...map.zones.filter((z) => z.keypoint).map((z) => Math.max(
      Math.hypot(z.keypoint.du_m, z.keypoint.dv_m), z.keypoint.lod95_h_m ?? 0, z.keypoint.lod95_v_m ?? 0)));
    const arrowScale = 60 / reach;
    // The areas' vectors to their own scale: the 95th percentile of their lengths 25 px.
    const lengths = map.zones.flatMap((z) => (z.vectors ? z.vectors.du_m.map((du, i) => Math.hypot(du, z.vectors.dv_m[i])) : []))
      .sort((p, q) => p - q);
    const areaScale = 25 / Math.max(1e-5, lengths.length ? lengths[Math.floor(0.95 * (lengths.length - 1))] : 0);
    const legends = [legend(limit)];
    if (map.zones.some((z) => z.keypoint)) {
      legends.push(arrowLegend(arrowScale, 'keypoint vectors along the wall', 'ellipse: LoD95; grey: within it'));
    }
    if (lengths.length) {
      legends.push(arrowLegend(areaScale, "3-D vectors of the areas along the wall", 'dark blue: beyond their LoD95; grey: within it; longer than 3 × the 95th percentile: cut'));
    }
    document.querySelector('#map-legend').replaceChildren(...legends);
    box.replaceChildren(...map.zones.map((z) => drawZone(z, limit, arrowScale, areaScale)));
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
