#!/usr/bin/env python3
"""garmcapctl waits out a busy station: against a stand-in garmcapd on loopback (Python's own
http.server, sharing no code with the daemon) that answers the marker route 503 with Retry-After
as the station does while another marker is laid, garmcapctl tries again after the seconds named
and writes the file once it is answered; a station busy for good ends in the 503's own error,
and an answer without Retry-After is not retried.

usage: garmcapctl_busy_test.py GARMCAPCTL
"""
import http.server
import json
import subprocess
import sys
import threading

BUSY = {"error": "another marker is being laid on this station; try again in a few seconds"}


class Station(http.server.BaseHTTPRequestHandler):
    busy_left = 0       # 503s still to give before the marker
    retry_after = "0"   # None: a 503 without Retry-After
    seen = []

    def do_GET(self):
        Station.seen.append(self.path)
        if Station.busy_left != 0:
            Station.busy_left -= 1
            body = json.dumps(BUSY).encode()
            self.send_response(503)
            if Station.retry_after is not None:
                self.send_header("Retry-After", Station.retry_after)
        else:
            body = json.dumps({"efficiency": 0.73, "length_cm": 120.5}).encode()
            self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)

    def log_message(self, *args):
        pass


def run(ctl, port):
    return subprocess.run(
        [ctl, "--url", "http://127.0.0.1:%d" % port, "export", "7", "--what", "marker.json",
         "--width", "150"],
        capture_output=True, text=True, timeout=60)


def main():
    ctl = sys.argv[1]
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), Station)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    port = server.server_address[1]
    failures = []

    # Busy twice, then laid: the file arrives, each wait said on stderr.
    Station.busy_left, Station.retry_after, Station.seen = 2, "1", []
    r = run(ctl, port)
    if r.returncode != 0 or json.loads(r.stdout or "null") != {"efficiency": 0.73,
                                                                "length_cm": 120.5}:
        failures.append("busy twice: exit %d, out %r, err %r" % (r.returncode, r.stdout, r.stderr))
    if r.stderr.count("trying again in 1 s") != 2 or "another marker" not in r.stderr:
        failures.append("busy twice: the waits are not said: %r" % r.stderr)
    if len(Station.seen) != 3 or any(p != "/api/items/7/marker.json?width=150"
                                     for p in Station.seen):
        failures.append("busy twice: requests %r" % Station.seen)

    # Busy for good: gives up after its attempts with the station's own message, exit 1.
    Station.busy_left, Station.retry_after, Station.seen = -1, "0", []
    r = run(ctl, port)
    if r.returncode != 1 or "HTTP 503: another marker" not in r.stderr:
        failures.append("busy for good: exit %d, err %r" % (r.returncode, r.stderr))
    if len(Station.seen) != 12:
        failures.append("busy for good: %d requests, want 12" % len(Station.seen))

    # A 503 without Retry-After (not the marker slot): not retried.
    Station.busy_left, Station.retry_after, Station.seen = 1, None, []
    r = run(ctl, port)
    if r.returncode != 1 or len(Station.seen) != 1:
        failures.append("no Retry-After: exit %d after %d requests" % (r.returncode,
                                                                      len(Station.seen)))
    server.shutdown()
    for f in failures:
        print("FAIL:", f)
    print("garmcapctl busy station: %s" % ("ok" if not failures else "%d failures" % len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
