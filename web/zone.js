// A zone's series (/zones/NAME): one quantity at a time over a window, the LoD95 as a band,
// the alarm levels as lines, alarm raises and acknowledgements and rejected epochs as marks,
// the keypoint model d(t, z) where the quantity has one, the thermal compensation where the
// quantity has a thermal model (measured, predicted and compensated together, with the
// epochs it could not compensate marked at the foot; ?thermal=0 hides them), and on request
// the air temperature or pressure on a second axis (?meteo=air_temperature_c or pressure_hpa).
// Drag to zoom (the server is asked again for the zoomed window, at full resolution when
// it fits the chart's width), shift-drag to pan, double-click to return to the window.
import {
  buttons, displayValue, element, formatTime, getJson, header, onEpochCommitted, showError, unit,
} from './common.js';

const zone = decodeURIComponent(location.pathname.replace(/^\/zones\//, ''));
const params = new URLSearchParams(location.search);
const windows = [['1 day', 86400], ['7 days', 7 * 86400], ['30 days', 30 * 86400],
  ['1 year', 365 * 86400], ['all', 0]];
let quantity = params.get('quantity');
let span = Number(params.get('window') ?? 7 * 86400);
const meteoChoices = [['no meteo', ''], ['air temperature', 'air_temperature_c'], ['pressure', 'pressure_hpa']];
let meteoField = params.get('meteo') ?? '';
let meteo = null;
let showThermal = params.get('thermal') !== '0';
let view = null;  // [from, to] in Unix seconds when zoomed in
let chart = null;
let series = null;

// The window: the zoomed view, else the chosen span back from the newest epoch.
function seriesUrl(format) {
  return windowUrl('/api/v1/series', { zone, quantity, format });
}

function windowUrl(path, fields) {
  const q = new URLSearchParams(fields);
  q.set('width', String(Math.max(100, document.querySelector('#chart').clientWidth)));
  if (view) {
    q.set('from', String(Math.floor(view[0])));
    q.set('to', String(Math.ceil(view[1])));
  } else if (span > 0) {
    q.set('from', String(window.tlsmonNewest - span));
  }
  return `${path}?${q}`;
}

// Rows for the chart: time, then [low, value, high] per series (the value's LoD95 band; the
// model and the meteo without a band), null where a series has no point at that time.
function chartRows(columns) {
  const byTime = new Map();
  columns.forEach((points, c) => {
    for (const [t, bar] of points) {
      if (!byTime.has(t)) byTime.set(t, new Array(columns.length).fill(null));
      byTime.get(t)[c] = bar;
    }
  });
  return [...byTime.keys()].sort((a, b) => a - b).map((t) => [new Date(t * 1000), ...byTime.get(t)]);
}

// The alarm levels of the rules watching the value (not its rate), as horizontal lines.
function levelLines(rules) {
  const lines = [];
  for (const r of rules) {
    const d = r.definition;
    if (!r.enabled || !d || d.rate_window_seconds !== null) continue;
    for (const [name, l] of Object.entries(d.levels)) {
      for (const side of ['high', 'low']) {
        if (l[side] !== null) lines.push({ rule: r.name, level: name, value: displayValue(quantity, l[side]) });
      }
    }
  }
  return lines;
}

const levelColour = { warning: '#d4a017', alert: '#e07000', alarm: '#c62828' };

// The thermal compensation's three series (docs/thermal.md) by role; the quantity shown is one
// of them, or a health ratio (then none is drawn beside it: another scale).
const thermalRoles = [
  ['measured', 'measured', '#1f5fa8', (base) => base],
  ['predicted', 'thermal prediction', '#00897b', (base) => base.replace(/_m$/, '_thermal_m')],
  ['compensated', 'compensated (measured − predicted)', '#ad1457', (base) => base.replace(/_m$/, '_compensated_m')],
];
const qualityColour = { no_model: 'rgba(120,120,120,0.45)', no_meteo: 'rgba(230,120,0,0.75)', extrapolated: 'rgba(200,170,0,0.6)' };

function thermalRole() {
  const t = series.thermal;
  if (!t) return null;
  const role = thermalRoles.find(([, , , name]) => name(t.quantity) === quantity);
  return role ? role[0] : null;
}

function bar(q, value, lod95) {
  const v = displayValue(q, value);
  const lod = lod95 === null ? 0 : displayValue(q, lod95);
  return [v - lod, v, v + lod];
}

function draw() {
  const columns = [series.points.map((p) => [p.t, bar(quantity, p.value, p.lod95)])];
  const role = thermalRole();
  const labels = ['time', `${quantity} [${unit(quantity)}]`];
  const colors = [role ? thermalRoles.find(([r]) => r === role)[2] : '#1f5fa8'];
  const perSeries = {};
  const thermalDrawn = [];
  document.querySelector('#thermal').hidden = !role;
  if (role && showThermal) {
    for (const [r, label, colour] of thermalRoles) {
      if (r === role) continue;
      columns.push(series.thermal[r].map(([t, v, lod]) => [t, bar(quantity, v, lod)]));
      labels.push(`${label} [${unit(quantity)}]`);
      colors.push(colour);
      perSeries[labels.at(-1)] = r === 'predicted' ? { strokePattern: [6, 3], strokeWidth: 1.5 } : {};
      thermalDrawn.push(r);
    }
  }
  if (series.model) {
    columns.push(series.model.points.map(([t, d]) => {
      const v = displayValue(quantity, d);
      return [t, [v, v, v]];
    }));
    labels.push(`model d(t, z = ${series.model.zone_height_m.toFixed(2)} m)`);
    colors.push('#6a1b9a');
    perSeries[labels.at(-1)] = { strokePattern: [6, 3], drawPoints: false, strokeWidth: 1.5 };
  }
  if (meteoField && meteo) {
    columns.push(meteo[meteoField].map(([t, v]) => [t, [v, v, v]]));
    labels.push(meteoField === 'pressure_hpa' ? 'pressure [hPa]' : 'air temperature [°C]');
    colors.push('#8a8a8a');
    perSeries[labels.at(-1)] = { axis: 'y2', drawPoints: false, strokeWidth: 1 };
  }
  const rows = chartRows(columns);
  const lines = levelLines(series.alarm_rules);
  const marks = series.alarm_events.filter((e) => ['raise', 'ack', 'clear', 'rtn'].some((k) => e.kind.startsWith(k)));
  const rejected = series.rejected_epochs;
  const notCompensated = role && showThermal ? series.thermal.not_compensated : [];
  const underlay = (canvas, area, g) => {
    canvas.save();
    for (const l of lines) {
      const y = g.toDomYCoord(l.value);
      canvas.strokeStyle = levelColour[l.level] || '#888';
      canvas.setLineDash([6, 4]);
      canvas.beginPath();
      canvas.moveTo(area.x, y);
      canvas.lineTo(area.x + area.w, y);
      canvas.stroke();
    }
    canvas.setLineDash([]);
    for (const m of marks) {
      const x = g.toDomXCoord(new Date(m.t * 1000));
      canvas.strokeStyle = m.kind.startsWith('raise') ? '#c62828' : '#2e7d32';
      canvas.beginPath();
      canvas.moveTo(x, area.y);
      canvas.lineTo(x, area.y + area.h);
      canvas.stroke();
    }
    canvas.fillStyle = 'rgba(120,120,120,0.35)';
    for (const r of rejected) {
      const x = g.toDomXCoord(new Date(r.t * 1000));
      canvas.fillRect(x - 1, area.y, 3, area.h);
    }
    // The thermal compensation's gaps: a strip at the foot over each run of epochs.
    for (const run of notCompensated) {
      const x0 = g.toDomXCoord(new Date((run.from - 450) * 1000));
      const x1 = g.toDomXCoord(new Date((run.to + 450) * 1000));
      canvas.fillStyle = qualityColour[run.quality] || 'rgba(120,120,120,0.45)';
      canvas.fillRect(x0, area.y + area.h - 8, Math.max(3, x1 - x0), 8);
    }
    canvas.restore();
  };
  const options = {
    labels,
    series: perSeries,
    connectSeparatedPoints: true,
    customBars: true,
    labelsUTC: true,
    drawPoints: rows.length < 400,
    pointSize: 2,
    ylabel: `${quantity} (${unit(quantity) || '1'})`,
    y2label: meteoField ? labels.at(-1) : null,
    axes: { y2: { drawGrid: false, independentTicks: true } },
    legend: 'follow',
    labelsDiv: document.querySelector('#legend'),
    underlayCallback: underlay,
    zoomCallback: (minX, maxX) => {
      view = chart && chart.isZoomed('x') ? [minX / 1000, maxX / 1000] : null;
      load();
    },
    colors,
  };
  if (series.points.length === 0) {
    document.querySelector('#chart').replaceChildren(element('p', { class: 'quiet', text: 'No point in this window.' }));
    chart = null;
    return;
  }
  if (chart && document.querySelector('#chart canvas') && chart.getLabels().length === labels.length) {
    chart.updateOptions({ file: rows, ...options, dateWindow: view ? [view[0] * 1000, view[1] * 1000] : null });
  } else {
    document.querySelector('#chart').replaceChildren();
    chart = new Dygraph(document.querySelector('#chart'), rows, options);
    window.tlsmonChart = chart;  // the chart's own data, for scripts and tests
  }
  window.tlsmonThermalDrawn = { roles: thermalDrawn, runs: notCompensated.length };
  const n = series.points.length;
  document.querySelector('#chart-note').textContent =
    `${n} point(s) shown of ${series.total} in the window` +
    (series.decimated ? ' (lowest and highest per pixel: zoom in for every epoch)' : ' (every epoch)') +
    `; ${lines.length} alarm level line(s), ${marks.length} alarm mark(s), ${rejected.length} rejected epoch(s)` +
    (series.model ? `; the model d(t, z) fitted at epoch ${series.model.epoch}` : '') +
    thermalNote(role, notCompensated) +
    (meteoField && meteo ? `; ${meteo[meteoField].length} meteo value(s) of ${meteo.total}` : '') + '.';
}

// What the thermal compensation adds to the note: the model and the epochs it left out.
function thermalNote(role, runs) {
  const t = series.thermal;
  if (!t) return '';
  if (!role) return `; thermal model v${t.model.version} of ${t.quantity}`;
  const m = t.model;
  const count = {};
  for (const r of runs) count[r.quality] = (count[r.quality] || 0) + r.epochs;
  const gaps = Object.entries(count).map(([q, n]) => `${n} ${q.replace('_', ' ')}`).join(', ');
  return `; thermal model v${m.version} (lags ${m.surface_lag_h} h + ${m.section_lag_h} h, ` +
    `σ ${displayValue(quantity, m.prediction_sigma).toFixed(2)} ${unit(quantity)}, ` +
    `${(100 * m.explained_share).toFixed(1)} % of the variance), trained ${formatTime(m.training_from)} – ` +
    `${formatTime(m.training_to)}` + (showThermal && gaps ? `; epochs marked at the foot: ${gaps}` : '');
}

async function load() {
  try {
    [series, meteo] = await Promise.all([getJson(seriesUrl('json')),
      meteoField ? getJson(windowUrl('/api/v1/meteo', {})) : null]);
    window.tlsmonSeries = series;  // what the chart holds, for scripts and tests
    window.tlsmonMeteo = meteo;
    draw();
    document.querySelector('#csv').href = seriesUrl('csv');
  } catch (e) {
    showError('#chart', e);
  }
}

async function start() {
  try {
    const [site, zones] = await Promise.all([getJson('/api/v1/site'), getJson('/api/v1/zones')]);
    header(site.station, '');
    const z = zones.find((x) => x.name === zone);
    document.querySelector('#zone-name').textContent = `Zone ${zone}`;
    document.title = `tlsmon — ${zone}`;
    if (!z || z.quantities.length === 0) {
      showError('#chart', new Error(z ? 'no result stored for this zone yet' : `no zone named ${zone}`));
      return;
    }
    if (!quantity || !z.quantities.includes(quantity)) quantity = z.quantities[0];
    const newest = site.last_epoch ? site.last_epoch.t : Math.floor(Date.now() / 1000);
    window.tlsmonNewest = newest;
    const pick = () => {
      buttons('#quantities', z.quantities.map((q) => [q, q]), (q) => q === quantity, (q) => { quantity = q; view = null; pick(); load(); });
      buttons('#windows', windows, (s) => s === span, (s) => { span = s; view = null; pick(); load(); });
      buttons('#meteo', meteoChoices, (m) => m === meteoField, (m) => { meteoField = m; pick(); load(); });
      buttons('#thermal', [['thermal parts', true], ['measured only', false]], (v) => v === showThermal,
        (v) => { showThermal = v; pick(); draw(); });
    };
    pick();
    await load();
    onEpochCommitted(async () => {
      const s = await getJson('/api/v1/site');
      if (s.last_epoch) window.tlsmonNewest = s.last_epoch.t;
      if (!view) load();
    });
  } catch (e) {
    showError('#chart', e);
  }
}

start();
