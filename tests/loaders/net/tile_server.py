#!/usr/bin/env python3
"""A local HTTP server for tests/loaders/net/ResourceTest.cpp: serves a directory, well or badly by path prefix.

    python3 tile_server.py DIR [--tls CERT KEY]

Binds 127.0.0.1 on a free port and prints the port as its first line of stdout; with --tls it speaks HTTPS with
that certificate and key (PEM). Paths:
    /FILE                  the file under DIR
    /status/CODE/FILE      that status and a short error page
    /stall/FILE            headers and part of the body, then nothing until the client goes away
    /drop/FILE             Content-Length of the whole file, half of it, then the socket closed
    /slow/FILE             the file in pieces with small sleeps between them; completes
    /nolength/FILE         the file without Content-Length, the end marked by closing the connection
    /redirect/N/FILE       N redirects (302) before the file
    /count/FILE            the file, the request counted; GET /requests returns the counts by path as JSON
    /goto?to=URL           a redirect (302) to URL, whatever its scheme
    /echo                  the request's headers as a JSON object
    /cache/POLICY/VALIDATOR/FILE
                           the file with caching headers, the request counted (as /count/; a 304 answered counted
                           again as "304 PATH"). POLICY: a number N (Cache-Control: max-age=N), "none" (no
                           Cache-Control), "no-store", "no-cache", or "expires" (Expires 100 s after Date).
                           VALIDATOR: "etag" (an ETag of the content; If-None-Match with it is answered 304),
                           "lastmod" (Last-Modified the file's time; If-Modified-Since not before it is answered
                           304) or "none".
Every request but /seen is recorded: GET /seen returns them as JSON, [path with its query, Authorization or null].
A request for /stall/ prints "arrived PATH" on stdout once its partial body is sent, so that a test can act while
the read is known to be waiting. The server exits when its stdin closes: a test process that dies leaves no server.
"""
import email.utils
import hashlib
import http.server
import json
import os
import select
import socket
import ssl
import sys
import urllib.parse
import threading
import time

ROOT = os.path.realpath(sys.argv[1])
counts = {}
counts_lock = threading.Lock()
seen = []
stdout_lock = threading.Lock()


def say(line):
    with stdout_lock:
        print(line, flush=True)


class Handler(http.server.BaseHTTPRequestHandler):
    protocol_version = "HTTP/1.1"  # keep-alive, as a real tile server: the client reuses its connections

    def log_message(self, *args):
        pass

    def file_bytes(self, rel):
        path = os.path.realpath(os.path.join(ROOT, rel))
        if not path.startswith(ROOT + os.sep) or not os.path.isfile(path):
            return None
        with open(path, "rb") as f:
            return f.read()

    def head(self, status, length=None, extra=()):
        self.send_response(status)
        self.send_header("Content-Type", "application/octet-stream")
        if length is not None:
            self.send_header("Content-Length", str(length))
        for k, v in extra:
            self.send_header(k, v)
        self.end_headers()

    def plain(self, status, body=b""):
        self.head(status, len(body))
        self.wfile.write(body)

    def do_GET(self):
        try:
            self.route()
        except (BrokenPipeError, ConnectionResetError):
            self.close_connection = True  # the client went away: nothing to say to it

    def route(self):
        path = self.path.split("?", 1)[0]
        parts = path.lstrip("/").split("/")
        kind = parts[0]
        if path == "/seen":
            with counts_lock:
                return self.plain(200, json.dumps(seen).encode())
        with counts_lock:
            seen.append([self.path, self.headers.get("Authorization")])
        if path == "/echo":
            return self.plain(200, json.dumps(dict(self.headers.items())).encode())
        if path == "/requests":
            with counts_lock:
                return self.plain(200, json.dumps(counts).encode())
        if kind == "status" and len(parts) >= 3:
            return self.plain(int(parts[1]), b"error page\n")
        if kind == "redirect" and len(parts) >= 3:
            n = int(parts[1])
            rest = "/".join(parts[2:])
            location = "/" + rest if n <= 1 else "/redirect/%d/%s" % (n - 1, rest)
            return self.head(302, 0, [("Location", location)])
        if path == "/goto":
            to = urllib.parse.parse_qs(urllib.parse.urlsplit(self.path).query).get("to", [""])[0]
            return self.head(302, 0, [("Location", to)])
        if kind == "count" or kind == "cache":
            with counts_lock:
                counts[path] = counts.get(path, 0) + 1
        if kind == "cache" and len(parts) >= 4:
            return self.cached(path, parts[1], parts[2], "/".join(parts[3:]))
        prefixed = kind in ("stall", "drop", "slow", "nolength", "count")
        data = self.file_bytes("/".join(parts[1:]) if prefixed else path.lstrip("/"))
        if data is None:
            return self.plain(404, b"not found\n")
        if kind == "stall":
            self.head(200, len(data))
            self.wfile.write(data[: min(1024, len(data) // 4)])
            self.wfile.flush()
            say("arrived " + path)
            self.wait_for_close()
        elif kind == "drop":
            self.head(200, len(data))
            self.wfile.write(data[: len(data) // 2])
            self.wfile.flush()
            self.close_connection = True
            self.connection.shutdown(socket.SHUT_RDWR)
        elif kind == "slow":
            self.head(200, len(data))
            piece = max(1, len(data) // 20)
            for i in range(0, len(data), piece):
                self.wfile.write(data[i : i + piece])
                self.wfile.flush()
                time.sleep(0.02)
        elif kind == "nolength":
            self.head(200, None, [("Connection", "close")])
            self.wfile.write(data)
            self.close_connection = True
        else:
            self.head(200, len(data))
            self.wfile.write(data)

    def cached(self, path, policy, validator, rel):
        data = self.file_bytes(rel)
        if data is None:
            return self.plain(404, b"not found\n")
        headers = []
        if policy.isdigit():
            headers.append(("Cache-Control", "max-age=" + policy))
        elif policy in ("no-store", "no-cache"):
            headers.append(("Cache-Control", policy))
        elif policy == "expires":
            headers.append(("Expires", self.date_time_string(time.time() + 100)))
        not_modified = False
        if validator == "etag":
            etag = '"%s"' % hashlib.sha1(data).hexdigest()[:16]
            headers.append(("ETag", etag))
            asked = self.headers.get("If-None-Match", "")
            not_modified = etag in asked or asked.strip() == "*"
        elif validator == "lastmod":
            mtime = int(os.path.getmtime(os.path.join(ROOT, rel)))
            headers.append(("Last-Modified", email.utils.formatdate(mtime, usegmt=True)))
            since = self.headers.get("If-Modified-Since")
            try:
                not_modified = since is not None and email.utils.parsedate_to_datetime(since).timestamp() >= mtime
            except (TypeError, ValueError):
                not_modified = False
        if not_modified:
            with counts_lock:
                counts["304 " + path] = counts.get("304 " + path, 0) + 1
            return self.head(304, None, headers)
        self.head(200, len(data), headers)
        self.wfile.write(data)

    def wait_for_close(self):
        # The client closes its end when it gives up (a stall timeout, a cancel): then recv returns b"".
        while True:
            readable, _, _ = select.select([self.connection], [], [], 1.0)
            if readable:
                try:
                    if not self.connection.recv(4096):
                        break
                except OSError:
                    break
        self.close_connection = True


def exit_when_stdin_closes():
    sys.stdin.buffer.read()
    os._exit(0)


class Server(http.server.ThreadingHTTPServer):
    daemon_threads = True


server = Server(("127.0.0.1", 0), Handler)
if len(sys.argv) == 5 and sys.argv[2] == "--tls":
    context = ssl.SSLContext(ssl.PROTOCOL_TLS_SERVER)
    context.load_cert_chain(sys.argv[3], sys.argv[4])
    server.socket = context.wrap_socket(server.socket, server_side=True)
threading.Thread(target=exit_when_stdin_closes, daemon=True).start()
say(str(server.server_address[1]))
server.serve_forever()
