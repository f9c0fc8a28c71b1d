// The site overview (/): the daemon, the last epoch and its registration, the backlog, the
// active alarms and every zone quantity's latest value ± LoD95, refreshed after each epoch.
import {
  element, formatAge, formatTime, formatValue, getJson, header, onEpochCommitted, showError,
  sparkline, stateClass, unit, zoneLink,
} from './common.js';

function row(label, value) {
  return element('tr', {}, element('th', { text: label }), element('td', { text: value }));
}

function daemonCard(site) {
  const age = site.daemon.heartbeat_age_s;
  const alive = age < 180;  // the loop beats at least every ingest.rescan_interval (60 s)
  return element('table', {},
    row('Status', alive ? 'running' : 'no heartbeat'),
    row('Heartbeat', `${formatTime(site.daemon.heartbeat)} (${formatAge(age)})`),
    row('Started', formatTime(site.daemon.started)),
    row('Reference epoch', site.reference_epoch ?? '—'));
}

function lastEpochCard(site) {
  const e = site.last_epoch;
  if (!e) return element('p', { text: 'no epoch processed yet' });
  const g = e.registration;
  const t = element('table', {},
    element('tr', {}, element('th', { text: 'Epoch' }),
      element('td', {}, element('a', { href: `/epochs/${e.id}`, text: `#${e.id}` }))),
    row('Acquired', formatTime(e.acquired)),
    row('Status', e.status),
    row('Processing', e.total_ms === null ? '—' : `${(e.total_ms / 1000).toFixed(1)} s`));
  if (g) {
    t.append(row('Registration', `${g.method}, ${g.accepted ? 'accepted' : 'not accepted'}`),
      row('Targets', `${g.targets_used} used, ${g.targets_left_out} left out`),
      row('s0', g.sigma0 === null ? '—' : g.sigma0.toFixed(2)),
      row('RMS of residuals', `${(g.rms_m * 1000).toFixed(2)} mm`));
    for (const s of g.sigma_at_zones) {
      t.append(row(`σ at ${s.zone}`, `${(s.sigma_3d_m * 1000).toFixed(2)} mm`));
    }
  } else {
    t.append(row('Registration', 'none stored'));
  }
  return t;
}

function backlogCard(site) {
  const e = site.epochs;
  return element('table', {},
    row('Backlog', `${site.backlog} epoch(s)${site.oldest_pending ? `, oldest ${formatTime(site.oldest_pending)}` : ''}`),
    row('Epochs', `${e.done} done, ${e.rejected} rejected, ${e.failed} failed`),
    row('Last failure', site.last_failure ? `#${site.last_failure.id} ${site.last_failure.status}: ${site.last_failure.reason}` : '—'),
    row('Database', `${(site.database.bytes / 1048576).toFixed(1)} MiB`),
    row('Disk free', site.disk_free_share === null ? '—' : `${(site.disk_free_share * 100).toFixed(1)} %`));
}

function alarmsTable(site) {
  if (site.alarms.length === 0) return element('p', { class: 'quiet', text: 'No active alarm.' });
  const t = element('table', { class: 'list' }, element('tr', {},
    ...['Rule', 'Zone', 'Quantity', 'State', 'Level', 'Since', 'Value'].map((h) => element('th', { text: h }))));
  for (const a of site.alarms) {
    t.append(element('tr', { 'data-rule': a.rule },
      element('td', { text: a.rule }),
      element('td', {}, zoneLink(a.zone)),
      element('td', { text: a.quantity }),
      element('td', {}, element('span', { class: stateClass(a.state), text: a.state })),
      element('td', { text: a.level }),
      element('td', { text: formatTime(a.since) }),
      element('td', { text: a.value === null ? '—' : `${formatValue(a.quantity, a.value)} ${unit(a.quantity)}` })));
  }
  return t;
}

function zonesTable(site) {
  const t = element('table', { class: 'list' }, element('tr', {},
    ...['Zone', 'Quantity', 'Latest', '± LoD95', 'Significant', 'Acquired', 'Last day'].map((h) => element('th', { text: h }))));
  for (const z of site.zones) {
    const link = element('a', { href: `/zones/${encodeURIComponent(z.name)}`, text: z.name });
    if (z.quantities.length === 0) {
      t.append(element('tr', {}, element('td', {}, link), element('td', { colSpan: 6, class: 'quiet', text: 'no result yet' })));
    }
    z.quantities.forEach((q, i) => {
      const p = q.latest;
      t.append(element('tr', {},
        element('td', {}, i === 0 ? link : ''),
        element('td', { text: q.quantity }),
        element('td', {
          class: 'value', 'data-zone': z.name, 'data-quantity': q.quantity,
          'data-epoch': p.epoch, 'data-value': p.value,
          text: `${formatValue(q.quantity, p.value)} ${unit(q.quantity)}`,
        }),
        element('td', { text: p.lod95 === null ? '—' : `± ${formatValue(q.quantity, p.lod95)}` }),
        element('td', { text: p.significant ? 'yes' : 'no', class: p.significant ? 'significant' : '' }),
        element('td', { text: formatTime(p.acquired) }),
        element('td', {}, sparkline(q.spark))));
    });
  }
  return t;
}

async function refresh() {
  try {
    const site = await getJson('/api/v1/site');
    window.tlsmonSite = site;  // what the page shows, for scripts and tests
    header(site.station, '/');
    document.title = `tlsmon — ${site.station}`;
    document.querySelector('#daemon .body').replaceChildren(daemonCard(site));
    document.querySelector('#last-epoch .body').replaceChildren(lastEpochCard(site));
    document.querySelector('#backlog .body').replaceChildren(backlogCard(site));
    document.querySelector('#alarms').replaceChildren(alarmsTable(site));
    document.querySelector('#zones').replaceChildren(zonesTable(site));
    document.querySelector('#updated').textContent = `Updated ${formatTime(site.now)}`;
  } catch (e) {
    showError('#zones', e);
  }
}

refresh();
onEpochCommitted(refresh);
