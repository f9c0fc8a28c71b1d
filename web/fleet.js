// The fleet's page (`tlsmon fleet serve`, docs/central.md): the sites, every zone quantity's
// newest value (filtered by |value| and quantity), and the series of the row chosen, each
// value with its 95 % bound as a band.
import { element, formatTime, formatValue, getJson, showError, unit, displayValue } from './common.js';

function table(columns, rows) {
  return element('table', { class: 'list' },
    element('tr', {}, ...columns.map(([label]) => element('th', { text: label }))),
    ...rows);
}

async function loadSites() {
  try {
    const sites = await getJson('/api/v1/fleet/sites');
    window.tlsmonFleetSites = sites;
    document.querySelector('#sites').replaceChildren(table(
      [['site'], ['location'], ['epochs'], ['newest epoch'], ['last forwarded'], ['entries']],
      sites.map((s) => element('tr', { 'data-site': s.site },
        element('td', { text: s.site }), element('td', { text: s.location ?? '' }),
        element('td', { text: String(s.epochs) }), element('td', { text: formatTime(s.newest_epoch) }),
        element('td', { text: formatTime(s.forwarded) }), element('td', { text: String(s.entries ?? 0) })))));
  } catch (e) {
    showError('#sites', e);
  }
}

async function loadStatus(filter) {
  try {
    const rows = await getJson(`/api/v1/fleet/status?${new URLSearchParams(filter)}`);
    window.tlsmonFleetStatus = rows;
    document.querySelector('#status').replaceChildren(table(
      [['site'], ['zone'], ['quantity'], ['acquired'], ['value'], ['95 % bound']],
      rows.map((r) => {
        const tr = element('tr', { 'data-site': r.site, 'data-zone': r.zone, 'data-quantity': r.quantity },
          element('td', { text: r.site }), element('td', { text: r.zone }),
          element('td', { text: r.quantity }), element('td', { text: formatTime(r.acquired) }),
          element('td', { class: r.significant ? 'value significant' : 'value', 'data-value': String(r.value),
            text: `${formatValue(r.quantity, r.value)} ${unit(r.quantity)}` }),
          element('td', { text: r.uncertainty === null ? '—' : `${formatValue(r.quantity, r.uncertainty)} ${unit(r.quantity)}` }));
        tr.style.cursor = 'pointer';
        tr.addEventListener('click', () => loadSeries(r.site, r.zone, r.quantity));
        return tr;
      })));
  } catch (e) {
    showError('#status', e);
  }
}

async function loadSeries(site, zone, quantity) {
  document.querySelector('#series-title').textContent = `Series: ${site} · ${zone} · ${quantity}`;
  try {
    const q = new URLSearchParams({ site, zone, quantity });
    const points = await getJson(`/api/v1/fleet/series?${q}`);
    window.tlsmonFleetSeries = { site, zone, quantity, points };
    const rows = points.map((p) => {
      const v = displayValue(quantity, p.value);
      const b = p.uncertainty === null ? 0 : displayValue(quantity, p.uncertainty);
      return [new Date(p.acquired), [v - b, v, v + b]];
    });
    document.querySelector('#chart').replaceChildren();
    window.tlsmonChart = new Dygraph(document.querySelector('#chart'), rows, {
      labels: ['time', `${quantity} [${unit(quantity)}]`], customBars: true, labelsUTC: true,
      drawPoints: rows.length < 400, pointSize: 2, colors: ['#1f5fa8'],
      ylabel: `${quantity} (${unit(quantity) || '1'})`,
    });
    document.querySelector('#chart-note').textContent = `${points.length} epoch(s) of ${site}, as forwarded.`;
  } catch (e) {
    showError('#chart', e);
  }
}

const form = document.querySelector('#filter');
form.addEventListener('submit', (ev) => {
  ev.preventDefault();
  const filter = {};
  for (const [k, v] of new FormData(form)) if (v) filter[k] = v;
  loadStatus(filter);
});
loadSites();
loadStatus({});
