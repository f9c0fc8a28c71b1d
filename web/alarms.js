// Alarms (/alarms): every rule's ISA-18.2 state and the alarm history, newest first. A
// logged-in operator acknowledges, shelves, unshelves, takes out of and returns to service,
// with a comment; each action goes to the daemon's alarm code and into the history with
// the operator's name.
import {
  element, formatTime, formatValue, getJson, header, onEpochCommitted, showError, stateClass, unit, zoneLink,
} from './common.js';

let session = null;  // {user, role, csrf} when logged in

async function post(url, body) {
  const headers = { 'Content-Type': 'application/json' };
  if (session) headers['X-CSRF-Token'] = session.csrf;
  const r = await fetch(url, { method: 'POST', headers, body: JSON.stringify(body) });
  const answer = await r.json();
  if (!r.ok) throw new Error(answer.error || `HTTP ${r.status}`);
  return answer;
}

function say(text, error = false) {
  const p = document.querySelector('#action-result');
  p.textContent = text;
  p.className = error ? 'error' : 'quiet';
}

// The actions the rule's state allows (ISA-18.2).
function actionsFor(a) {
  const out = [];
  if (a.state === 'unack' || a.state === 'rtn_unack') out.push(['ack', 'Acknowledge']);
  if (a.state === 'shelved') out.push(['unshelve', 'Unshelve']);
  else if (a.state !== 'out_of_service' && a.state !== 'normal') out.push(['shelve', 'Shelve']);
  if (a.state === 'out_of_service') out.push(['in-service', 'Return to service']);
  else out.push(['out-of-service', 'Out of service']);
  return out;
}

async function act(action, rule) {
  const body = { rule, comment: document.querySelector('#comment').value };
  if (action === 'shelve') {
    const hours = Number(document.querySelector('#shelve-hours').value);
    body.until = new Date(Date.now() + hours * 3600e3).toISOString().replace(/\.\d+Z$/, 'Z');
  }
  try {
    const r = await post(`/api/v1/alarms/${action}`, body);
    say(`${action} ${rule}: ${r.changed} rule(s) changed, by ${r.by}.`);
    document.querySelector('#comment').value = '';
  } catch (e) {
    say(`${action} ${rule}: ${e.message}`, true);
  }
  refresh();
}

function canAct() {
  return session && (session.role === 'operator' || session.role === 'admin');
}

async function refresh() {
  try {
    const [site, alarms] = await Promise.all([getJson('/api/v1/site'), getJson('/api/v1/alarms')]);
    header(site.station, '/alarms');
    const quantityOf = Object.fromEntries(alarms.states.map((a) => [a.rule, a.quantity]));
    const columns = ['Rule', 'Zone', 'Quantity', 'State', 'Level', 'Since', 'Value', 'Shelved until'];
    if (canAct()) columns.push('Actions');
    const states = element('table', { class: 'list' }, element('tr', {},
      ...columns.map((h) => element('th', { text: h }))));
    for (const a of alarms.states) {
      const row = element('tr', { 'data-rule': a.rule },
        element('td', { text: a.rule }),
        element('td', {}, zoneLink(a.zone)),
        element('td', { text: a.quantity }),
        element('td', {}, element('span', { class: stateClass(a.state), text: a.state })),
        element('td', { text: a.level }),
        element('td', { text: formatTime(a.since) }),
        element('td', { text: a.value === null ? '—' : `${formatValue(a.quantity, a.value)} ${unit(a.quantity)}` }),
        element('td', { text: formatTime(a.shelved_until) }));
      if (canAct()) {
        const cell = element('td', { class: 'actions' });
        for (const [action, label] of actionsFor(a)) {
          const b = element('button', { type: 'button', text: label, class: `action-${action}` });
          b.addEventListener('click', () => act(action, a.rule));
          cell.append(b);
        }
        row.append(cell);
      }
      states.append(row);
    }
    const history = element('table', { class: 'list' }, element('tr', {},
      ...['Time', 'Rule', 'Event', 'Level', 'Value', 'By', 'Message'].map((h) => element('th', { text: h }))));
    for (const e of alarms.events.slice().reverse()) {
      const q = quantityOf[e.rule] ?? '';
      history.append(element('tr', {},
        element('td', { text: formatTime(e.time) }),
        element('td', { text: e.rule }),
        element('td', { text: e.kind }),
        element('td', { text: e.level }),
        element('td', { text: e.value === null ? '—' : `${formatValue(q, e.value)} ${unit(q)}` }),
        element('td', { text: e.actor }),
        element('td', { text: e.message })));
    }
    document.querySelector('#states').replaceChildren(states);
    document.querySelector('#history').replaceChildren(history);
  } catch (e) {
    showError('#states', e);
  }
}

async function loadSession() {
  const s = await getJson('/api/v1/session');
  session = s.user ? s : null;
  document.querySelector('#login').hidden = session !== null;
  document.querySelector('#logged-in').hidden = session === null;
  if (session) {
    document.querySelector('#who').textContent = `Logged in as ${session.user} (${session.role})`;
    document.querySelector('#comment').disabled = !canAct();
  }
}

document.querySelector('#login').addEventListener('submit', async (ev) => {
  ev.preventDefault();
  const form = ev.target;
  try {
    await post('/api/v1/login', { user: form.user.value, password: form.password.value });
    form.password.value = '';
    say('');
  } catch (e) {
    say(`Login refused: ${e.message}`, true);
  }
  await loadSession();
  refresh();
});

document.querySelector('#logout').addEventListener('click', async () => {
  try {
    await post('/api/v1/logout', {});
  } catch (e) {
    say(e.message, true);
  }
  await loadSession();
  refresh();
});

await loadSession();
refresh();
onEpochCommitted(refresh);
