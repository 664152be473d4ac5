#!/usr/bin/env python3
"""Open a page in headless Chromium and wait, in real time, until its title leaves a starting value.

Usage: chromium_title.py URL [--wait-while TITLE] [--timeout SECONDS]

Prints the page's last title and exits 0 once it differs from TITLE (default "loading"); exits 1
with the title it was stuck at after SECONDS. Chromium is driven through the DevTools protocol
over a pipe (--remote-debugging-pipe: JSON messages ended by NUL, Chromium reads fd 3 and writes
fd 4), so the wait is on the page itself. --virtual-time-budget is not used for pages that play
media: virtual time runs ahead of the media pipeline's own threads, and Chromium 156 dumped a
page whose video had not loaded yet in 4 of 5 runs on an idle host.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time


class Browser:
    def __init__(self, extra_args):
        to_chrome_r, self._to_chrome = os.pipe()
        self._from_chrome, from_chrome_w = os.pipe()
        self._profile = tempfile.TemporaryDirectory(prefix="chromium-title-")
        # The child sees the pipe ends as fds 3 (it reads) and 4 (it writes); both are first
        # moved above 4 so that placing one cannot overwrite the other. Popen keeps pass_fds
        # open through the fd closing that follows preexec_fn.
        def place_fds():
            reads, writes = os.dup(to_chrome_r) + 10, os.dup(from_chrome_w) + 10
            os.dup2(to_chrome_r, reads)
            os.dup2(from_chrome_w, writes)
            os.dup2(reads, 3)
            os.dup2(writes, 4)
        self._proc = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--remote-debugging-pipe",
             "--user-data-dir=" + self._profile.name, *extra_args, "about:blank"],
            preexec_fn=place_fds, pass_fds=(3, 4),
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_chrome_r)
        os.close(from_chrome_w)
        self._next_id = 0
        self._buffer = b""

    def call(self, method, params=None, session=None, deadline=None):
        self._next_id += 1
        message = {"id": self._next_id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._to_chrome, json.dumps(message).encode() + b"\0")
        while True:  # events arrive between replies; only the reply to this call is wanted
            reply = self._read(deadline)
            if reply.get("id") == self._next_id:
                if "error" in reply:
                    raise RuntimeError("%s: %s" % (method, reply["error"]))
                return reply.get("result", {})

    def _read(self, deadline):
        while b"\0" not in self._buffer:
            if deadline is not None and time.monotonic() > deadline:
                raise TimeoutError("Chromium did not answer in time")
            chunk = os.read(self._from_chrome, 65536)
            if not chunk:
                raise RuntimeError("Chromium closed the pipe (exit %s)" % self._proc.poll())
            self._buffer += chunk
        message, self._buffer = self._buffer.split(b"\0", 1)
        return json.loads(message)

    def close(self):
        try:
            self.call("Browser.close", deadline=time.monotonic() + 10)
        except Exception:
            pass
        try:
            self._proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()
        os.close(self._to_chrome)
        os.close(self._from_chrome)
        self._profile.cleanup()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("url")
    parser.add_argument("--wait-while", default="loading")
    parser.add_argument("--timeout", type=float, default=60.0)
    args, chromium_args = parser.parse_known_args()
    deadline = time.monotonic() + args.timeout
    browser = Browser(chromium_args)
    title = None
    try:
        target = browser.call("Target.createTarget", {"url": "about:blank"}, deadline=deadline)["targetId"]
        session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True},
                               deadline=deadline)["sessionId"]
        browser.call("Page.navigate", {"url": args.url}, session=session, deadline=deadline)
        while time.monotonic() < deadline:
            # Until the navigation commits the evaluation still sees about:blank, and until the
            # page is parsed its title is empty.
            result = browser.call("Runtime.evaluate",
                                  {"expression": "[location.href, document.readyState, document.title]",
                                   "returnByValue": True},
                                  session=session, deadline=deadline)
            href, state, title = result.get("result", {}).get("value") or ["", "", None]
            if href != "about:blank" and state != "loading" and title != args.wait_while:
                print(title)
                return 0
            time.sleep(0.1)
    finally:
        browser.close()
    print(title if title is not None else "")
    print("chromium_title: the title stayed '%s' for %.0f s" % (title, args.timeout), file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
