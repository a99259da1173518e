"""rcl-web: build the browser site, serve it for a local try.

    rcl-web build DIR                         the static site into DIR
    rcl-web serve DIR [--port N] [--no-browser]   on http://127.0.0.1:N/

Any static web server can serve DIR; `serve` adds the cross-origin
isolation headers the page wants (COOP same-origin, COEP require-corp:
shared memory, hence Ctrl-C and Stop inside a running word).
"""
import argparse
import functools
import http.server
import os
import sys
import threading
import webbrowser

from rcl.web.build import BuildError, build

TYPES = {".mjs": "text/javascript", ".js": "text/javascript", ".wasm": "application/wasm",
         ".json": "application/json", ".whl": "application/zip", ".zip": "application/zip",
         ".css": "text/css", ".html": "text/html; charset=utf-8"}


class Handler(http.server.SimpleHTTPRequestHandler):
    """Static files with the isolation headers; quiet."""

    extensions_map = dict(http.server.SimpleHTTPRequestHandler.extensions_map, **TYPES)

    def end_headers(self):
        self.send_header("Cross-Origin-Opener-Policy", "same-origin")
        self.send_header("Cross-Origin-Embedder-Policy", "require-corp")
        self.send_header("Cross-Origin-Resource-Policy", "same-origin")
        self.send_header("Cache-Control", "no-cache")
        super().end_headers()

    def log_message(self, format, *args):
        pass


def make_server(folder, port=8020):
    """-> an HTTP server for folder on the loopback (port 0: any free one)."""
    handler = functools.partial(Handler, directory=folder)
    return http.server.ThreadingHTTPServer(("127.0.0.1", port), handler)


def serve(folder, port, browser):
    if not os.path.isfile(os.path.join(folder, "site.json")):
        sys.stderr.write("rcl-web: %s holds no built site: run `rcl-web build %s` first\n"
                         % (folder, folder))
        return 2
    try:
        server = make_server(folder, port)
    except OSError as e:
        sys.stderr.write("rcl-web: cannot listen on 127.0.0.1:%d: %s\n" % (port, e.strerror or e))
        return 1
    url = "http://127.0.0.1:%d/" % server.server_address[1]
    print("rcl-web: serving %s on %s (Ctrl-C stops)" % (folder, url), flush=True)
    if browser:
        threading.Thread(target=webbrowser.open, args=(url,), daemon=True).start()
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    finally:
        server.server_close()
    return 0


def parse_args(argv):
    p = argparse.ArgumentParser(prog="rcl-web", description="rcl in a browser tab: build the "
                                "static site, or serve it on the loopback for a local try.")
    sub = p.add_subparsers(dest="command", required=True)
    b = sub.add_parser("build", help="build the static site into DIR (needs node and npm)")
    b.add_argument("dir")
    s = sub.add_parser("serve", help="serve a built site with the isolation headers")
    s.add_argument("dir")
    s.add_argument("--port", type=int, default=8020)
    s.add_argument("--no-browser", action="store_true", help="do not open a browser")
    return p.parse_args(argv)


def main(argv=None):
    args = parse_args(argv)
    if args.command == "build":
        try:
            files = build(args.dir)
        except BuildError as e:
            sys.stderr.write("rcl-web: %s\n" % e)
            return 1
        size = sum(os.path.getsize(os.path.join(args.dir, f)) for f in files)
        print("rcl-web: built %d files, %.1f MB, in %s; try it: rcl-web serve %s"
              % (len(files), size / 1e6, args.dir, args.dir))
        return 0
    return serve(args.dir, args.port, not args.no_browser)


if __name__ == "__main__":
    sys.exit(main())
