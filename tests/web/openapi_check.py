#!/usr/bin/python3
"""The dashboard API against its description (docs/openapi.yaml), on a running daemon.

Every schema of the description must be a valid JSON Schema (2020-12, OpenAPI 3.1's dialect)
and every $ref must resolve. Then real requests, one or more per operation: each answer's
status must be one the operation documents, its content type one that status documents, and a
JSON body must validate against that status's schema (additionalProperties: false in the
description makes an undocumented key a failure). Every operation of the description must have
been exercised.

    openapi_check.py SPEC BASE_URL ZONE QUANTITY EPOCH OPERATOR PASSWORD RULE
    openapi_check.py SPEC BASE_URL CAMPAIGN
    openapi_check.py SPEC BASE_URL --series ZONE QUANTITY

The second form checks only the campaign operations, on a daemon that stored CAMPAIGN (the
first form's database has none, so it sees their empty and missing answers only); the third
only the series operation, on a zone quantity the first form's database does not hold (a
thermally compensated one). Prints {"checked": N, "operations": M, "failures": [...]} and exits 1 on any failure.
Uses python3-yaml and python3-jsonschema from Debian; urllib for HTTP.
"""
import datetime
import http.cookiejar
import json
import re
import sys
import urllib.error
import urllib.parse
import urllib.request

import jsonschema
import yaml

campaign_only = len(sys.argv) == 4
series_only = len(sys.argv) == 6 and sys.argv[3] == '--series'
if campaign_only:
    spec_path, base, campaign = sys.argv[1:4]
elif series_only:
    spec_path, base, _, zone, quantity = sys.argv[1:6]
else:
    spec_path, base, zone, quantity, epoch, user, password, rule = sys.argv[1:9]


class UniqueKeyLoader(yaml.SafeLoader):
    """YAML keeps the last of two equal keys; a description must not have two."""


def unique_mapping(loader, node, deep=False):
    keys = [loader.construct_object(k, deep=deep) for k, _ in node.value]
    repeated = {k for k in keys if keys.count(k) > 1}
    if repeated:
        raise yaml.constructor.ConstructorError(
            None, None, f'key(s) {sorted(repeated)} given twice', node.start_mark)
    return loader.construct_mapping(node, deep)


UniqueKeyLoader.add_constructor(yaml.resolver.BaseResolver.DEFAULT_MAPPING_TAG, unique_mapping)
spec = yaml.load(open(spec_path, encoding='utf-8'), Loader=UniqueKeyLoader)
failures = []
checked = 0
exercised = set()

# The description's own schemas and references.
validator_class = jsonschema.Draft202012Validator
resolver = jsonschema.RefResolver.from_schema(spec)
for name, schema in spec.get('components', {}).get('schemas', {}).items():
    try:
        validator_class.check_schema(schema)
    except jsonschema.SchemaError as e:
        failures.append(f'components/schemas/{name}: not a valid JSON Schema: {e.message}')


def walk_refs(node, where):
    if isinstance(node, dict):
        if '$ref' in node:
            try:
                resolver.resolve(node['$ref'])
            except jsonschema.RefResolutionError as e:
                failures.append(f'{where}: $ref {node["$ref"]} does not resolve: {e}')
        for k, v in node.items():
            walk_refs(v, f'{where}/{k}')
    elif isinstance(node, list):
        for i, v in enumerate(node):
            walk_refs(v, f'{where}/{i}')


walk_refs(spec, '#')


def deref(node):
    while isinstance(node, dict) and '$ref' in node:
        node = resolver.resolve(node['$ref'])[1]
    return node


def operation_of(method, path):
    for template, ops in spec['paths'].items():
        pattern = '^' + re.sub(r'\{[^}]+\}', '[^/]+', template) + '$'
        if re.match(pattern, path) and method.lower() in ops:
            return template, ops[method.lower()]
    return None, None


jar = http.cookiejar.CookieJar()
opener = urllib.request.build_opener(urllib.request.HTTPCookieProcessor(jar))


def request(method, path, body=None, headers=None, expect=None, read_all=True):
    """One request, checked against the description; returns (status, parsed JSON or None)."""
    global checked
    url = base + path
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(url, data=data, method=method, headers=headers or {})
    if data is not None:
        req.add_header('Content-Type', 'application/json')
    try:
        answer = opener.open(req, timeout=20)
    except urllib.error.HTTPError as e:
        answer = e
    status = answer.status if hasattr(answer, 'status') else answer.code
    content_type = (answer.headers.get('Content-Type') or '').split(';')[0].strip()
    raw = answer.read() if read_all else answer.read(64)
    answer.close()
    where = f'{method} {path} -> {status}'
    if expect is not None and status != expect:
        failures.append(f'{where}: expected {expect}')
    template, op = operation_of(method, urllib.parse.urlsplit(path).path)
    if op is None:
        failures.append(f'{where}: no such operation in the description')
        return status, None
    exercised.add((method.upper(), template))
    responses = op.get('responses', {})
    documented = deref(responses.get(str(status)) or responses.get('default'))
    if documented is None:
        failures.append(f'{where}: status not documented (documented: {sorted(responses)})')
        return status, None
    content = documented.get('content', {})
    if content_type not in content:
        failures.append(f'{where}: content type {content_type!r} not documented '
                        f'(documented: {sorted(content)})')
        return status, None
    checked += 1
    if content_type != 'application/json':
        return status, None
    try:
        parsed = json.loads(raw)
    except ValueError as e:
        failures.append(f'{where}: not JSON: {e}')
        return status, None
    schema = content[content_type].get('schema')
    if schema is not None:
        validator = validator_class(schema, resolver=resolver)
        for error in sorted(validator.iter_errors(parsed), key=lambda e: list(e.path))[:5]:
            location = '/'.join(str(p) for p in error.path)
            failures.append(f'{where}: at /{location}: {error.message[:300]}')
    return status, parsed


def campaign_requests(campaign):
    request('GET', '/api/v1/campaigns', expect=200)
    request('GET', '/api/v1/campaigns?from=2000-01-01T00:00:00Z', expect=200)
    request('GET', '/api/v1/campaigns?to=never', expect=400)
    request('GET', '/api/v1/campaigns/999999', expect=404)
    request('GET', '/api/v1/campaigns/999999/points', expect=404)
    request('GET', '/api/v1/campaigns/1/points?max=0', expect=400)
    if campaign is not None:
        request('GET', f'/api/v1/campaigns/{campaign}', expect=200)
        request('GET', f'/api/v1/campaigns/{campaign}/points', expect=200)
        request('GET', f'/api/v1/campaigns/{campaign}/points?max=100', expect=200)


def series_requests():
    q = urllib.parse.quote
    series = f'/api/v1/series?zone={q(zone)}&quantity={q(quantity)}'
    request('GET', series, expect=200)
    request('GET', series + '&width=100&from=2000-01-01&to=2100-01-01', expect=200)
    request('GET', series + '&format=csv', expect=200)
    request('GET', f'/api/v1/series?zone={q(zone)}', expect=400)
    request('GET', series + '&from=yesterday', expect=400)


def every_request():
    request('GET', '/api/v1/site', expect=200)
    request('GET', '/api/v1/zones', expect=200)
    series_requests()
    request('GET', '/api/v1/meteo', expect=200)
    request('GET', '/api/v1/meteo?width=3&from=2000-01-01', expect=200)
    request('GET', '/api/v1/meteo?width=wide', expect=400)
    request('GET', '/api/v1/calibration', expect=200)
    request('GET', '/api/v1/calibration?from=2000-01-01T00:00:00Z', expect=200)
    request('GET', '/api/v1/calibration?to=never', expect=400)
    request('GET', '/api/v1/events', expect=200)
    request('GET', '/api/v1/events?kind=http_login', expect=200)
    request('GET', '/api/v1/alarms', expect=200)
    request('GET', '/api/v1/epochs', expect=200)
    request('GET', f'/api/v1/epochs/{epoch}', expect=200)
    request('GET', '/api/v1/epochs/999999', expect=404)
    request('GET', f'/api/v1/epochs/{epoch}/corepoints', expect=200)
    request('GET', '/api/v1/stream', expect=200, read_all=False)
    request('GET', '/api/v1/session', expect=200)
    request('POST', '/api/v1/alarms/ack', body={'rule': rule}, expect=401)
    request('POST', '/api/v1/logout', expect=401)
    status, login = request('POST', '/api/v1/login', body={'user': user, 'password': password},
                            expect=200)
    csrf = {'X-CSRF-Token': login['csrf']} if status == 200 and login else {}
    request('GET', '/api/v1/session', expect=200)
    request('POST', '/api/v1/alarms/ack', body={'rule': rule}, expect=403)  # no CSRF token
    request('POST', '/api/v1/alarms/ack', body={'rule': 'no such rule'}, headers=csrf, expect=400)
    request('POST', '/api/v1/alarms/out-of-service', body={'rule': rule, 'comment': 'openapi'},
            headers=csrf, expect=200)
    request('POST', '/api/v1/alarms/in-service', body={'rule': rule}, headers=csrf, expect=200)
    in_an_hour = (datetime.datetime.now(datetime.timezone.utc) + datetime.timedelta(hours=1))
    request('POST', '/api/v1/alarms/shelve', headers=csrf, expect=200,
            body={'rule': rule, 'comment': 'openapi', 'until': in_an_hour.strftime('%Y-%m-%dT%H:%M:%SZ')})
    request('POST', '/api/v1/alarms/shelve', body={'rule': rule, 'comment': 'x', 'until': 'soon'},
            headers=csrf, expect=400)
    request('POST', '/api/v1/alarms/unshelve', body={'rule': rule}, headers=csrf, expect=200)
    request('POST', '/api/v1/alarms/ack', body={'rule': rule}, headers=csrf)
    request('POST', '/api/v1/logout', headers=csrf, expect=200)

    campaign_requests(None)


if campaign_only:
    campaign_requests(campaign)
elif series_only:
    series_requests()
else:
    every_request()

operations = {(m.upper(), p) for p, ops in spec['paths'].items() for m in ops
              if m in ('get', 'post', 'put', 'delete', 'patch')}
if campaign_only:
    operations = {(m, p) for m, p in operations if p.startswith('/api/v1/campaigns')}
if series_only:
    operations = {(m, p) for m, p in operations if p == '/api/v1/series'}
for method, path in sorted(operations - exercised):
    failures.append(f'{method} {path}: described but not exercised')

print(json.dumps({'checked': checked, 'operations': len(operations), 'failures': failures},
                 indent=1))
sys.exit(1 if failures else 0)
