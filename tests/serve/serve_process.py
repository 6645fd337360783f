"""Starts build/bin/serve on a free localhost port for the serve tests and the load benchmark."""
import contextlib
import subprocess


@contextlib.contextmanager
def running_serve(serve_exe, *args):
    """Yields the page's URL (http://127.0.0.1:PORT/); stops the server afterwards."""
    p = subprocess.Popen([str(serve_exe), "--port", "0", *map(str, args)], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    try:
        line = p.stdout.readline().strip()
        if not line.startswith("serve: http://127.0.0.1:"):
            raise RuntimeError(f"serve did not start: {line!r} {p.stderr.read() if p.poll() is not None else ''}")
        yield line.split()[1]
        if p.poll() is not None:
            raise RuntimeError(f"serve died (status {p.returncode}): {p.stderr.read()}")
    finally:
        p.terminate()
        p.wait(timeout=10)
