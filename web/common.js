// Shared by every page of the dashboard: fetching the API, units, times, the header, the
// live update (server-sent events, polling when the server has no stream left).

export async function getJson(url) {
  const r = await fetch(url, { headers: { Accept: 'application/json' } });
  const body = await r.json();
  if (!r.ok) throw new Error(body.error || `${url}: HTTP ${r.status}`);
  return body;
}

// Lengths are stored in metres (quantities ending in _m) and shown in millimetres.
export function isLength(quantity) {
  return quantity.endsWith('_m');
}
export function displayValue(quantity, v) {
  return v === null || v === undefined ? null : isLength(quantity) ? v * 1000 : v;
}
export function unit(quantity) {
  return isLength(quantity) ? 'mm' : '';
}
export function formatValue(quantity, v, digits = 2) {
  const d = displayValue(quantity, v);
  if (d === null) return '—';
  if (!isLength(quantity) && Number.isInteger(d)) return String(d);  // counts
  return d.toFixed(isLength(quantity) ? digits : 3);
}

// A zone's name as a link to its page; the system alarms' "(system)" is not a zone.
export function zoneLink(zone) {
  if (!zone || zone.startsWith('(')) return zone || '';
  return element('a', { href: `/zones/${encodeURIComponent(zone)}`, text: zone });
}

// "2026-11-29T06:00:00Z" -> "2026-11-29 06:00:00 UTC": the site's records are in UTC.
export function formatTime(iso) {
  return iso ? iso.replace('T', ' ').replace('Z', ' UTC') : '—';
}
export function formatAge(seconds) {
  if (seconds < 90) return `${Math.round(seconds)} s ago`;
  if (seconds < 5400) return `${Math.round(seconds / 60)} min ago`;
  if (seconds < 172800) return `${(seconds / 3600).toFixed(1)} h ago`;
  return `${(seconds / 86400).toFixed(1)} d ago`;
}

export function element(tag, attributes = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attributes)) {
    if (v === undefined || v === null) continue;
    if (k === 'class') e.className = v;
    else if (k === 'text') e.textContent = v;
    else if (k.startsWith('data-')) e.setAttribute(k, v);
    else e[k] = v;
  }
  for (const c of children) e.append(c);
  return e;
}

// The header of every page: the station and the navigation.
export function header(station, current) {
  const nav = element('nav');
  for (const [href, label] of [['/', 'Overview'], ['/alarms', 'Alarms'], ['/events', 'Events'],
    ['/calibration', 'Calibration'], ['/campaigns', 'Campaigns']]) {
    nav.append(element('a', { href, text: label, class: href === current ? 'current' : '' }));
  }
  const h = document.querySelector('header');
  h.replaceChildren(element('span', { class: 'brand', text: 'tlsmon' }),
    element('span', { class: 'station', text: station || '' }), nav);
}

// ISA-18.2 alarm states and their colours (docs/alarms.md).
export function stateClass(state) {
  return `state state-${state.replaceAll('_', '-')}`;
}

// Calls `refresh` after each epoch commit: server-sent events, or every 30 s when the
// server refuses another stream (http.max_event_streams) or the stream breaks.
export function onEpochCommitted(refresh) {
  let polling = null;
  const poll = () => {
    if (!polling) polling = setInterval(refresh, 30000);
  };
  if (!window.EventSource) return poll();
  const source = new EventSource('/api/v1/stream');
  source.onopen = () => { window.tlsmonStreamOpen = true; };
  source.addEventListener('epoch', (e) => refresh(JSON.parse(e.data)));
  source.addEventListener('alarm', (e) => refresh(JSON.parse(e.data)));
  source.onerror = () => {
    if (source.readyState === EventSource.CLOSED) poll();
  };
}

// A small line of the recent values, as an SVG polyline.
export function sparkline(points, width = 120, height = 28) {
  const ns = 'http://www.w3.org/2000/svg';
  const svg = document.createElementNS(ns, 'svg');
  svg.setAttribute('width', width);
  svg.setAttribute('height', height);
  svg.setAttribute('class', 'spark');
  if (points.length < 2) return svg;
  const t0 = points[0][0], t1 = points[points.length - 1][0];
  const vs = points.map((p) => p[1]);
  const lo = Math.min(...vs), hi = Math.max(...vs);
  const x = (t) => (t1 > t0 ? ((t - t0) / (t1 - t0)) * (width - 2) + 1 : width / 2);
  const y = (v) => (hi > lo ? height - 2 - ((v - lo) / (hi - lo)) * (height - 4) : height / 2);
  const line = document.createElementNS(ns, 'polyline');
  line.setAttribute('points', points.map((p) => `${x(p[0]).toFixed(1)},${y(p[1]).toFixed(1)}`).join(' '));
  svg.append(line);
  return svg;
}

// A row of choice buttons in `where`: [label, value] items, the current one highlighted.
export function buttons(where, items, isCurrent, choose) {
  const box = document.querySelector(where);
  box.replaceChildren(...items.map(([label, value]) => {
    const b = element('button', { text: label, class: isCurrent(value) ? 'current' : '' });
    b.addEventListener('click', () => choose(value));
    return b;
  }));
}

export function showError(where, error) {
  const box = document.querySelector(where);
  box.replaceChildren(element('p', { class: 'error', text: String(error.message || error) }));
}
