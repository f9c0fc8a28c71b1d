#!/usr/bin/python3
"""Drives Debian's chromium (headless, through chromium-driver and python3-selenium) over
the dashboard and prints, as one JSON document, what each page shows: the values read from
the page's DOM and its chart's own data (never a screenshot), the browser console's errors,
and a screenshot per page in OUT_DIR. The comparison with the database is the caller's
(tests/daemon/test_process_dashboard.cpp).

  dashboard_browser.py pages BASE OUT_DIR ZONE QUANTITY EPOCH
  dashboard_browser.py operator BASE OUT_DIR USER PASSWORD RULE COMMENT
  dashboard_browser.py live BASE OUT_DIR READY_FILE TIMEOUT_S
  dashboard_browser.py campaign BASE OUT_DIR CAMPAIGN
  dashboard_browser.py thermal BASE OUT_DIR ZONE QUANTITY
  dashboard_browser.py fleet BASE OUT_DIR
"""
import json
import sys
import time

from selenium import webdriver
from selenium.webdriver.chrome.service import Service


def browser():
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
              "--window-size=1400,1000", "--lang=en-GB"):
        options.add_argument(a)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def wait_for(driver, script, seconds=20):
    """Polls a JavaScript expression until it is truthy; returns its value."""
    end = time.time() + seconds
    while time.time() < end:
        value = driver.execute_script("return " + script)
        if value:
            return value
        time.sleep(0.1)
    raise TimeoutError(f"{driver.current_url}: not true within {seconds} s: {script}")


def console_errors(driver):
    return [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def visit(driver, url, ready, out_dir, name):
    driver.get(url)
    wait_for(driver, ready)
    time.sleep(0.3)  # the last paint
    driver.save_screenshot(f"{out_dir}/{name}.png")
    return console_errors(driver)


def pages(base, out_dir, zone, quantity, epoch):
    d = browser()
    report = {"errors": {}}
    try:
        report["errors"]["overview"] = visit(
            d, base + "/", "document.querySelectorAll('td.value').length > 0", out_dir, "overview")
        report["overview"] = d.execute_script("""
            return {
              values: [...document.querySelectorAll('td.value')].map(td => ({
                zone: td.dataset.zone, quantity: td.dataset.quantity,
                epoch: Number(td.dataset.epoch), value: Number(td.dataset.value),
                text: td.textContent})),
              last_epoch: document.querySelector('#last-epoch a').textContent,
              alarms: [...document.querySelectorAll('#alarms tr[data-rule]')].map(tr => ({
                rule: tr.dataset.rule, state: tr.querySelector('.state').textContent})),
              station: document.querySelector('header .station').textContent };""")

        from urllib.parse import quote
        report["errors"]["zone"] = visit(
            d, f"{base}/zones/{quote(zone)}?quantity={quote(quantity)}&window=0",
            "window.tlsmonChart && window.tlsmonChart.numRows() > 0", out_dir, "zone")
        report["zone"] = d.execute_script("""
            const g = window.tlsmonChart, rows = [];
            for (let i = 0; i < g.numRows(); ++i) {
              const v = g.getValue(i, 1);  // [value - LoD95, value, value + LoD95]
              rows.push([g.getValue(i, 0), Array.isArray(v) ? v[1] : v]);
            }
            return { rows, total: window.tlsmonSeries.total,
                     note: document.querySelector('#chart-note').textContent,
                     csv: document.querySelector('#csv').href };""")

        # The same zone with the air temperature on the second axis: the chart's last column.
        report["errors"]["zone-meteo"] = visit(
            d, f"{base}/zones/{quote(zone)}?quantity={quote(quantity)}&window=0&meteo=air_temperature_c",
            "window.tlsmonChart && window.tlsmonMeteo && window.tlsmonChart.getLabels().length === 3",
            out_dir, "zone-meteo")
        report["zone_meteo"] = d.execute_script("""
            const g = window.tlsmonChart, values = [];
            for (let i = 0; i < g.numRows(); ++i) {
              const v = g.getValue(i, 2);
              if (v !== null && Array.isArray(v) && v[1] !== null) values.push([g.getValue(i, 0), v[1]]);
            }
            return { values, label: g.getLabels()[2] };""")

        report["errors"]["epoch"] = visit(
            d, f"{base}/epochs/{epoch}", "window.tlsmonMap && document.querySelectorAll('canvas.map').length > 0",
            out_dir, "epoch")
        report["epoch"] = d.execute_script("""
            const cores = new Set();
            for (const z of window.tlsmonMap.zones) for (const k of z.core) cores.add(k);
            return { marks: [...document.querySelectorAll('canvas.map')].map(c => Number(c.dataset.marks)),
                     zones: window.tlsmonMap.zones.map(z => z.zone),
                     distinct_core_points: cores.size,
                     arrows: Object.fromEntries([...document.querySelectorAll('canvas.map')].map(
                       (c, i) => [window.tlsmonMap.zones[i].zone, Number(c.dataset.arrows)])),
                     area_arrows: Object.fromEntries([...document.querySelectorAll('canvas.map')].map(
                       (c, i) => [window.tlsmonMap.zones[i].zone, Number(c.dataset.areaArrows)])),
                     area_dv: Object.fromEntries(window.tlsmonMap.zones.filter(z => z.vectors).map(
                       z => [z.zone, [z.vectors.dv_m, z.frame]])),
                     vectors: Object.fromEntries(window.tlsmonMap.zones.filter(z => z.keypoint).map(
                       z => [z.zone, [z.keypoint.du_m, z.keypoint.dv_m, z.frame]])),
                     title: document.querySelector('#title').textContent };""")

        report["errors"]["alarms"] = visit(
            d, base + "/alarms", "document.querySelectorAll('#states tr[data-rule]').length > 0",
            out_dir, "alarms")
        report["alarms"] = d.execute_script("""
            return [...document.querySelectorAll('#states tr[data-rule]')].map(tr => ({
              rule: tr.dataset.rule, state: tr.querySelector('.state').textContent}));""")

        # Calibration over every epoch: the table's rows as shown (the shares' counts).
        report["errors"]["calibration"] = visit(
            d, base + "/calibration?window=0",
            "window.tlsmonCalibration && document.querySelectorAll('#calibration tr[data-method]').length > 0",
            out_dir, "calibration")
        report["calibration"] = d.execute_script("""
            return { epochs: window.tlsmonCalibration.epochs,
                     rows: [...document.querySelectorAll('#calibration tr[data-method]')].map(tr => {
                       const within = tr.querySelectorAll('td[data-within]');
                       return { method: tr.dataset.method, part: tr.dataset.part,
                                n: Number(tr.children[2].textContent),
                                within68: Number(within[0].dataset.within),
                                within95: Number(within[1].dataset.within),
                                rms_mm: tr.children[5].textContent,
                                verdict95: tr.querySelector('td.verdict:last-child').textContent }; }) };""")

        report["errors"]["events"] = visit(
            d, base + "/events", "document.querySelectorAll('#events tr').length > 1", out_dir, "events")
        report["events"] = d.execute_script(
            "return document.querySelectorAll('#events tr').length - 1;")
    finally:
        d.quit()
    return report


def operator(base, out_dir, user, password, rule, comment):
    """On /alarms: logs in through the form, acknowledges RULE with COMMENT by its button,
    and waits until the page shows the rule acknowledged."""
    d = browser()
    try:
        d.get(base + "/alarms")
        wait_for(d, "!document.querySelector('#login').hidden")
        d.find_element("id", "login-user").send_keys(user)
        d.find_element("id", "login-password").send_keys(password)
        d.find_element("id", "login-submit").click()
        row = f"document.querySelector('#states tr[data-rule=\"{rule}\"]')"
        wait_for(d, f"{row} && {row}.querySelector('button.action-ack')")
        d.find_element("id", "comment").send_keys(comment)
        d.execute_script(f"{row}.querySelector('button.action-ack').click()")
        state = wait_for(d, f"{row} && {row}.querySelector('.state').textContent === 'ack' && 'ack'")
        time.sleep(0.3)
        d.save_screenshot(f"{out_dir}/alarms_acknowledged.png")
        return {"state": state, "who": d.find_element("id", "who").text,
                "result": d.find_element("id", "action-result").text,
                "errors": console_errors(d)}
    finally:
        d.quit()


def live(base, out_dir, ready_file, timeout):
    """The overview, left open: the last epoch it shows before and after the next commit,
    with no reload by the script."""
    d = browser()
    try:
        d.get(base + "/")
        before = wait_for(d, "document.querySelector('#last-epoch a') && document.querySelector('#last-epoch a').textContent")
        wait_for(d, "window.tlsmonStreamOpen === true")
        with open(ready_file, "w") as f:
            f.write(before)
        end = time.time() + timeout
        after = before
        while time.time() < end and after == before:
            time.sleep(0.2)
            after = d.execute_script("return document.querySelector('#last-epoch a').textContent")
        d.save_screenshot(f"{out_dir}/overview_live.png")
        return {"before": before, "after": after, "errors": console_errors(d),
                "navigations": d.execute_script("return performance.getEntriesByType('navigation').length")}
    finally:
        d.quit()


def campaign(base, out_dir, number):
    """The campaigns' list and one campaign's page: rows, what was drawn, the segments."""
    d = browser()
    report = {"errors": {}}
    try:
        report["errors"]["campaigns"] = visit(
            d, base + "/campaigns", "window.tlsmonCampaigns !== undefined", out_dir, "campaigns")
        report["list"] = d.execute_script("""
            return [...document.querySelectorAll('tr[data-campaign]')].map((r) => ({
              campaign: Number(r.dataset.campaign),
              cells: [...r.querySelectorAll('td')].map((c) => c.textContent),
              link: r.querySelector('a').getAttribute('href')}));""")
        report["errors"]["campaign"] = visit(
            d, f"{base}/campaigns/{number}",
            "window.tlsmonCampaign && window.tlsmonCampaign.drawn.points > 0", out_dir, "campaign")
        report["page"] = d.execute_script("""
            const c = window.tlsmonCampaign;
            return {
              title: document.querySelector('#title').textContent,
              drawn: c.drawn,
              views: [...document.querySelectorAll('figure[data-view]')].map((f) => f.dataset.view),
              segments: document.querySelectorAll('tr[data-segment]').length,
              frame: document.querySelector('#frame').textContent,
              moved: document.querySelector('#summary').textContent,
            };""")
    finally:
        d.quit()
    return report


def chart_columns(d):
    """The chart's labels and, per series, its [time, value, 95 % bound] where it has a point."""
    return d.execute_script("""
        const g = window.tlsmonChart, labels = g.getLabels(), columns = {};
        for (let c = 1; c < labels.length; ++c) {
          columns[labels[c]] = [];
          for (let i = 0; i < g.numRows(); ++i) {
            const v = g.getValue(i, c);
            if (v !== null && Array.isArray(v) && v[1] !== null)
              columns[labels[c]].push([g.getValue(i, 0) / 1000, v[1], v[2] - v[1]]);
          }
        }
        return { labels, columns, drawn: window.tlsmonThermalDrawn,
                 note: document.querySelector('#chart-note').textContent,
                 toggle_shown: !document.querySelector('#thermal').hidden };""")


def thermal(base, out_dir, zone, base_quantity):
    """A compensated quantity's zone page over every epoch: the measured series with its
    prediction and residual, the same from the residual's page, and after 'measured only'."""
    from urllib.parse import quote
    d = browser()
    report = {"errors": {}}
    try:
        compensated = base_quantity[:-2] + "_compensated_m"
        for name, q in (("measured", base_quantity), ("compensated", compensated)):
            report["errors"][name] = visit(
                d, f"{base}/zones/{quote(zone)}?quantity={quote(q)}&window=0",
                "window.tlsmonChart && window.tlsmonThermalDrawn && window.tlsmonChart.numRows() > 0",
                out_dir, "zone-thermal-" + name)
            report[name] = chart_columns(d)
        buttons = d.find_elements("css selector", "#thermal button")
        [b for b in buttons if b.text == "measured only"][0].click()
        wait_for(d, "window.tlsmonThermalDrawn.roles.length === 0")
        report["measured_only"] = chart_columns(d)
        report["errors"]["measured_only"] = console_errors(d)
    finally:
        d.quit()
    return report


def fleet(base, out_dir):
    """The fleet's page: its sites and newest values as shown, then the first value's row
    clicked and its series as the chart holds it."""
    d = browser()
    report = {"errors": {}}
    try:
        report["errors"]["fleet"] = visit(
            d, base + "/", "document.querySelectorAll('#status tr[data-zone]').length > 0 &&"
            " document.querySelectorAll('#sites tr[data-site]').length > 0", out_dir, "fleet")
        report["sites"] = d.execute_script("""
            return [...document.querySelectorAll('#sites tr[data-site]')].map(
              tr => [...tr.querySelectorAll('td')].map(td => td.textContent));""")
        report["status"] = d.execute_script("""
            return [...document.querySelectorAll('#status tr[data-zone]')].map(tr => ({
              site: tr.dataset.site, zone: tr.dataset.zone, quantity: tr.dataset.quantity,
              value: Number(tr.querySelector('td.value').dataset.value),
              text: tr.querySelector('td.value').textContent}));""")
        d.execute_script("document.querySelector('#status tr[data-zone]').click()")
        wait_for(d, "window.tlsmonChart && window.tlsmonChart.numRows() > 0")
        time.sleep(0.3)
        d.save_screenshot(f"{out_dir}/fleet-series.png")
        report["series"] = d.execute_script("""
            const g = window.tlsmonChart, s = window.tlsmonFleetSeries, rows = [];
            for (let i = 0; i < g.numRows(); ++i) rows.push([g.getValue(i, 0) / 1000, g.getValue(i, 1)[1]]);
            return { site: s.site, zone: s.zone, quantity: s.quantity, rows,
                     title: document.querySelector('#series-title').textContent };""")
        report["errors"]["series"] = console_errors(d)
    finally:
        d.quit()
    return report


if __name__ == "__main__":
    mode, base, out_dir = sys.argv[1:4]
    if mode == "pages":
        result = pages(base, out_dir, sys.argv[4], sys.argv[5], int(sys.argv[6]))
    elif mode == "operator":
        result = operator(base, out_dir, *sys.argv[4:8])
    elif mode == "campaign":
        result = campaign(base, out_dir, int(sys.argv[4]))
    elif mode == "thermal":
        result = thermal(base, out_dir, sys.argv[4], sys.argv[5])
    elif mode == "fleet":
        result = fleet(base, out_dir)
    else:
        result = live(base, out_dir, sys.argv[4], float(sys.argv[5]))
    print(json.dumps(result))
