#!/usr/bin/env python3
"""Real receivers for the notification tests (tests/daemon/test_process_notify.cpp).

An SMTP server (aiosmtpd, Debian's python3-aiosmtpd) that requires STARTTLS and a login
before it takes mail, and an HTTP server (the standard library's) that takes webhook POSTs
carrying the expected bearer token, answering 503 to the first --refuse of them. Every
message taken is written into --out as one JSON file (mail-N.json, hook-N.json), every
refusal counted in refused.txt. Prints "ready" once both listen; runs until killed.
"""
import argparse
import itertools
import json
import os
import ssl
import sys
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

from aiosmtpd.controller import Controller
from aiosmtpd.smtp import AuthResult, LoginPassword

parser = argparse.ArgumentParser()
parser.add_argument("--smtp-port", type=int, required=True)
parser.add_argument("--http-port", type=int, required=True)
parser.add_argument("--cert", required=True)
parser.add_argument("--key", required=True)
parser.add_argument("--user", required=True)
parser.add_argument("--password", required=True)
parser.add_argument("--token", required=True)
parser.add_argument("--refuse", type=int, default=0)
parser.add_argument("--out", required=True)
args = parser.parse_args()

counter = itertools.count(1)
lock = threading.Lock()


def write(kind, record):
    with lock:
        n = next(counter)
        path = os.path.join(args.out, "%s-%d.json" % (kind, n))
        with open(path + ".part", "w") as f:
            json.dump(record, f)
        os.rename(path + ".part", path)


def refused(why):
    with lock:
        with open(os.path.join(args.out, "refused.txt"), "a") as f:
            f.write(why + "\n")


class Mail:
    async def handle_DATA(self, server, session, envelope):
        write("mail", {
            "tls": session.ssl is not None,
            "login": (session.login_data or b"").decode(),
            "from": envelope.mail_from,
            "to": envelope.rcpt_tos,
            "data": envelope.content.decode("utf-8", "replace"),
        })
        return "250 OK"


def authenticator(server, session, envelope, mechanism, auth_data):
    ok = (isinstance(auth_data, LoginPassword) and auth_data.login == args.user.encode()
          and auth_data.password == args.password.encode())
    if not ok:
        refused("smtp login")
    return AuthResult(success=ok, handled=False, auth_data=auth_data if ok else None)


tls = ssl.create_default_context(ssl.Purpose.CLIENT_AUTH)
tls.load_cert_chain(args.cert, args.key)
smtp = Controller(Mail(), hostname="127.0.0.1", port=args.smtp_port, tls_context=tls,
                  require_starttls=True, auth_required=True, auth_require_tls=True,
                  authenticator=authenticator)
smtp.start()

posts = itertools.count(1)


class Hook(BaseHTTPRequestHandler):
    def do_POST(self):
        body = self.rfile.read(int(self.headers.get("Content-Length", "0")))
        if self.headers.get("Authorization") != "Bearer " + args.token:
            refused("hook token")
            self.send_response(401)
            self.end_headers()
            return
        if next(posts) <= args.refuse:
            refused("hook 503")
            self.send_response(503)
            self.end_headers()
            self.wfile.write(b"busy, try later")
            return
        write("hook", {"content_type": self.headers.get("Content-Type"),
                       "notification": self.headers.get("X-tlsmon-Notification"),
                       "body": json.loads(body)})
        self.send_response(204)
        self.end_headers()

    def log_message(self, *a):
        pass


http = ThreadingHTTPServer(("127.0.0.1", args.http_port), Hook)
threading.Thread(target=http.serve_forever, daemon=True).start()
print("ready", flush=True)
while True:
    time.sleep(3600)
