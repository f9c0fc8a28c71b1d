// The operator log (/events): system and alarm events, newest first, filtered by kind and
// time (the filter is kept in the address, so a view can be sent to a colleague).
import { element, formatTime, getJson, header, onEpochCommitted, showError } from './common.js';

const form = document.querySelector('#filter');

async function refresh() {
  const q = new URLSearchParams(location.search);
  for (const name of ['kind', 'from', 'to']) form.elements[name].value = q.get(name) ?? '';
  try {
    const [site, events] = await Promise.all([getJson('/api/v1/site'), getJson(`/api/v1/events?${q}`)]);
    header(site.station, '/events');
    const t = element('table', { class: 'list' }, element('tr', {},
      ...['Time', 'Source', 'Level', 'Kind', 'Rule', 'Actor', 'Epoch', 'Message'].map((h) => element('th', { text: h }))));
    for (const e of events.slice().reverse()) {
      t.append(element('tr', { class: `level-${e.level}` },
        element('td', { text: formatTime(e.time) }),
        element('td', { text: e.source }),
        element('td', { text: e.level }),
        element('td', { text: e.kind }),
        element('td', { text: e.rule }),
        element('td', { text: e.actor }),
        element('td', {}, e.epoch === null ? '' : element('a', { href: `/epochs/${e.epoch}`, text: `#${e.epoch}` })),
        element('td', { text: e.message })));
    }
    document.querySelector('#events').replaceChildren(
      element('p', { class: 'quiet', text: `${events.length} event(s)` }), t);
  } catch (e) {
    showError('#events', e);
  }
}

form.addEventListener('submit', (ev) => {
  ev.preventDefault();
  const q = new URLSearchParams();
  for (const name of ['kind', 'from', 'to']) {
    if (form.elements[name].value) q.set(name, form.elements[name].value);
  }
  history.replaceState(null, '', `/events${q.toString() ? `?${q}` : ''}`);
  refresh();
});

refresh();
onEpochCommitted(refresh);
