"""Run a `vtube` command with its stderr on a pseudo-terminal (100 columns), as a user at a terminal would."""

from __future__ import annotations

import fcntl
import os
import pty
import select
import struct
import subprocess
import sys
import termios


def stderr_on_a_terminal(args: list[str], timeout_s: float = 300.0) -> tuple[int, bytes]:
    """The exit code of ``vtube ARGS`` and what it wrote to its terminal (stderr)."""
    main_fd, terminal = pty.openpty()
    fcntl.ioctl(terminal, termios.TIOCSWINSZ, struct.pack('HHHH', 24, 100, 0, 0))  # tqdm needs a width
    process = subprocess.Popen([sys.executable, '-m', 'vtube', *args], stdout=subprocess.DEVNULL, stderr=terminal)
    os.close(terminal)
    drawn = b''
    while True:  # read as it is written: a closed terminal may drop what was not read
        ready, _, _ = select.select([main_fd], [], [], 0.1)
        try:
            chunk = os.read(main_fd, 4096) if ready else b''
        except OSError:  # the terminal's other side closed
            break
        drawn += chunk
        if not chunk and process.poll() is not None:
            break
    os.close(main_fd)
    return process.wait(timeout=timeout_s), drawn


def stderr_on_a_pipe(args: list[str], timeout_s: float = 300.0) -> tuple[int, str]:
    """The exit code of ``vtube ARGS`` and its stderr, read through a pipe."""
    done = subprocess.run(
        [sys.executable, '-m', 'vtube', *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        timeout=timeout_s,
        check=False,
    )
    return done.returncode, done.stderr
