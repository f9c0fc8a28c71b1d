// One campaign (/campaigns/N): its summary, the frame it was found in, and — as the study
// draws them — each registered segment's translation as an arrow from its centroid, in plan
// (x, y) and in elevation (x, z), over the points it kept coloured by their C2C distance,
// framed on the segmented structure.
// Only observed components are drawn; a segment that observes neither of a view's two
// directions gets a cross. Red: the segment differs from the others (p < α); blue: it does not;
// grey: not tested. The arrows share one scale, with its bar.
import { element, formatTime, getJson, header, showError } from './common.js';
import { frameText, movedAsOne } from './campaigns.js';
import { colourBar, roundLength, scaleBar } from './map_legend.js';

const id = Number(location.pathname.split('/').pop());
const mm = (m, digits = 1) => (m === null || m === undefined ? '—' : `${(m * 1000).toFixed(digits)} mm`);
const WIDTH = 640, HEIGHT = 420, MARGIN = 24;

function row(label, value) {
  return element('tr', {}, element('th', { text: label }), element('td', { text: value }));
}

// Light yellow (0) to dark red (the campaign's 95th percentile of C2C and beyond).
function heat(t) {
  const c = Math.max(0, Math.min(1, t));
  return `rgb(${255 - c * 90 | 0},${235 - c * 215 | 0},${170 - c * 150 | 0})`;
}

function heatLegend(limit) {
  return colourBar(heat, 'C2C 0 mm', `${(limit * 1000).toFixed(0)} mm`,
    ' (grey: no reference point within reach)');
}

function arrowColour(s) {
  return s.differs === null ? '#777' : s.differs ? '#c62828' : '#1565c0';
}

// One view: `a`, `b` the axes drawn (0 x, 1 y, 2 z) across and up.
function view(points, segments, a, b, label, mPerMmArrow, limit) {
  const cols = [points.x, points.y, points.z];
  const origin = points.origin;
  // The view frames the segmented structure (with a margin), not the far ground a walker's
  // scanner reaches: points beyond are left out.
  const framed = points.segment.some((s) => s >= 0);
  let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
  for (let i = 0; i < points.shown; ++i) {
    if (framed && points.segment[i] < 0) continue;
    const u = cols[a][i], v = cols[b][i];
    lo = [Math.min(lo[0], u), Math.min(lo[1], v)];
    hi = [Math.max(hi[0], u), Math.max(hi[1], v)];
  }
  const pad = 0.1 * Math.max(hi[0] - lo[0], hi[1] - lo[1]);
  lo = [lo[0] - pad, lo[1] - pad];
  hi = [hi[0] + pad, hi[1] + pad];
  const scale = Math.min((WIDTH - 2 * MARGIN) / (hi[0] - lo[0] || 1), (HEIGHT - 2 * MARGIN) / (hi[1] - lo[1] || 1));
  const px = (u) => MARGIN + (u - lo[0]) * scale;
  const py = (v) => HEIGHT - MARGIN - (v - lo[1]) * scale;
  const canvas = element('canvas', { class: 'map', width: WIDTH, height: HEIGHT });
  const ctx = canvas.getContext('2d');
  for (let i = 0; i < points.shown; ++i) {
    const u = cols[a][i], v = cols[b][i];
    if (u < lo[0] || u > hi[0] || v < lo[1] || v > hi[1]) continue;
    const d = points.c2c_m[i];
    ctx.fillStyle = d === null ? '#cfcfcf' : heat(d / limit);
    ctx.fillRect(px(u) - 1, py(v) - 1, 2, 2);
  }
  let arrows = 0, crosses = 0;
  for (const s of segments) {
    if (!s.centroid || s.outcome !== 'registered') continue;
    const u = px(s.centroid[a] - origin[a]), v = py(s.centroid[b] - origin[b]);
    const ta = s.t[a], tb = s.t[b];
    ctx.strokeStyle = ctx.fillStyle = arrowColour(s);
    ctx.lineWidth = 2;
    if (ta === null && tb === null) {
      ctx.beginPath();
      ctx.moveTo(u - 5, v - 5); ctx.lineTo(u + 5, v + 5);
      ctx.moveTo(u - 5, v + 5); ctx.lineTo(u + 5, v - 5);
      ctx.stroke();
      ++crosses;
      continue;
    }
    // 1 mm of translation drawn as mPerMmArrow metres of the view.
    const tu = u + (ta ?? 0) * 1000 * mPerMmArrow * scale, tv = v - (tb ?? 0) * 1000 * mPerMmArrow * scale;
    ctx.beginPath();
    ctx.moveTo(u, v);
    ctx.lineTo(tu, tv);
    ctx.stroke();
    const angle = Math.atan2(tv - v, tu - u), head = Math.min(8, Math.hypot(tu - u, tv - v) * 0.5);
    ctx.beginPath();
    ctx.moveTo(tu, tv);
    ctx.lineTo(tu - head * Math.cos(angle - 0.4), tv - head * Math.sin(angle - 0.4));
    ctx.lineTo(tu - head * Math.cos(angle + 0.4), tv - head * Math.sin(angle + 0.4));
    ctx.fill();
    ctx.beginPath();
    ctx.arc(u, v, 2.5, 0, 2 * Math.PI);
    ctx.fill();
    ++arrows;
  }
  const names = ['x', 'y', 'z'];
  const figure = element('figure', { 'data-view': label },
    element('figcaption', { text: `${label} (${names[a]} across, ${names[b]} up; ${((hi[0] - lo[0])).toFixed(1)} m wide)` }), canvas);
  return { figure, arrows, crosses, scale };
}

// 1 mm of translation as metres of the drawing: the largest observed translation a tenth of
// the segmented structure's width.
function arrowScale(points, segments) {
  let width = 0;
  const framed = points.segment.some((s) => s >= 0);
  for (const col of [points.x, points.y]) {
    let lo = Infinity, hi = -Infinity;
    col.forEach((v, i) => {
      if (framed && points.segment[i] < 0) return;
      lo = Math.min(lo, v);
      hi = Math.max(hi, v);
    });
    width = Math.max(width, hi - lo);
  }
  let largest = 0;
  for (const s of segments) for (const t of s.t) if (t !== null) largest = Math.max(largest, Math.abs(t));
  return largest > 0 ? (0.1 * width) / (largest * 1000) : 1;
}

// The arrows' scale: a round number of millimetres drawn about 60 px long.
function arrowLegend(mPerMm, pxPerMetre) {
  const length = roundLength(60 / (mPerMm * pxPerMetre));
  return scaleBar(length * mPerMm * pxPerMetre, 'translation', `${Number(length.toPrecision(2))} mm`,
    'plan; red: differs from the others, blue: does not, ×: neither direction observed');
}

function segmentTable(segments) {
  const head = ['Segment', 'Class', 'Points', 'Outcome', 'Reference segment', 'tx', 'ty', 'tz',
    'σ tx', 'σ ty', 'σ tz', 'Test p', 'C2C mean'];
  const t = element('table', { class: 'list segments' },
    element('tr', {}, ...head.map((h) => element('th', { text: h }))));
  for (const s of segments) {
    const p = s.test_p === null ? '—' : s.test_p < 1e-4 ? '< 0.0001' : s.test_p.toFixed(4);
    t.append(element('tr', { 'data-segment': String(s.segment) },
      element('td', { text: String(s.segment) }),
      element('td', { text: s.class }),
      element('td', { class: 'value', text: s.points.toLocaleString('en-GB') }),
      element('td', { text: s.outcome }),
      element('td', { text: s.reference_segment === null ? '—' : String(s.reference_segment) }),
      ...s.t.map((v) => element('td', { class: 'value', text: mm(v, 2) })),
      ...s.sigma_t.map((v) => element('td', { class: 'value', text: mm(v, 2) })),
      element('td', { class: s.differs ? 'significant' : '', text: p }),
      element('td', { class: 'value', text: mm(s.c2c_mean_m) })));
  }
  return t;
}

async function load() {
  try {
    const site = await getJson('/api/v1/site');
    header(site.station, '/campaigns');
    const { campaign: c, segments } = await getJson(`/api/v1/campaigns/${id}`);
    document.querySelector('#title').textContent = `Campaign ${c.id}: ${c.instrument} (${c.kind}), ${formatTime(c.acquired)}`;
    document.querySelector('#summary').replaceChildren(element('table', {},
      row('Points', `${c.points.toLocaleString('en-GB')} (ground ${c.ground_points.toLocaleString('en-GB')})`),
      row('Segments registered', `${c.registered_segments} of ${c.segments}`),
      row('Moved as one', movedAsOne(c)),
      row('C2C', `mean ${mm(c.c2c_mean_m)}, median ${mm(c.c2c_median_m)}, 95 % ${mm(c.c2c_p95_m)}`),
      row('Reference epoch', String(c.reference_epoch)),
      row('File', c.file)));
    const f = c.frame;
    const heading = f ? (Math.atan2(f[4], f[0]) * 180) / Math.PI : null;
    document.querySelector('#frame').replaceChildren(element('table', {},
      row('Frame', frameText(c)),
      row('Heading onto the reference', heading === null ? '—' : `${heading.toFixed(3)}°`),
      row('Shift', f ? `${f[3].toFixed(3)}, ${f[7].toFixed(3)}, ${f[11].toFixed(3)} m` : '—'),
      row('Global registration', `${c.global_pairs.toLocaleString('en-GB')} pairs, RMSE ${mm(c.global_rmse_m)}`),
      row('Comparison', `${c.seconds.toFixed(1)} s`)));
    document.querySelector('#segments').replaceChildren(segmentTable(segments));
    let drawn = { points: 0, arrows: 0, crosses: 0 };
    try {
      const points = await getJson(`/api/v1/campaigns/${id}/points?max=60000`);
      const limit = c.c2c_p95_m || 0.05;
      const mPerMm = arrowScale(points, segments);
      const plan = view(points, segments, 0, 1, 'plan', mPerMm, limit);
      const elevation = view(points, segments, 0, 2, 'elevation', mPerMm, limit);
      document.querySelector('#legend').replaceChildren(heatLegend(limit), arrowLegend(mPerMm, plan.scale));
      document.querySelector('#maps').replaceChildren(plan.figure, elevation.figure);
      drawn = { points: points.shown, total: points.total, arrows: plan.arrows, crosses: plan.crosses };
    } catch (e) {
      showError('#maps', e);
    }
    window.tlsmonCampaign = { campaign: c, segments, drawn };  // for scripts and tests
  } catch (e) {
    showError('#summary', e);
  }
}

load();
