"""Key files of secure sessions, as `troupe keygen NAME` writes them and the
troupe CLI reads them (wire/noise/key_file.h, wire/cli/README.md):

    NAME      "troupe-x25519-secret <64 hex digits>", readable by its owner
              only (mode 0600): a client's identity
    NAME.pub  "troupe-x25519 <64 hex digits> NAME": what the other side is given

and the user's known nodes (as SSH's known_hosts), one node a line,
"HOST:PORT <64 hex digits>" (an IPv6 host in brackets); blank lines and lines
starting with '#' are skipped.

Plain file reading: no cryptography here (the key pair of a secret is the
noise module's), so it works without PyNaCl.
"""

from __future__ import annotations

import os
import stat
import string

_SECRET_TAG = "troupe-x25519-secret"
_PUBLIC_TAG = "troupe-x25519"
_HEX = set(string.hexdigits)
#: X25519 keys, bytes.
KEY_BYTES = 32


class KeyFileError(ValueError):
    """A key that cannot be used: a missing or malformed key file, a secret
    key others can read, a node the known-nodes file does not name."""


def key_hex(key: bytes) -> str:
    """64 lowercase hex digits."""
    return bytes(key).hex()


def parse_key_hex(text: str) -> bytes | None:
    """The key that 64 hex digits spell, or None when `text` is not that."""
    if len(text) != 2 * KEY_BYTES or not set(text) <= _HEX:
        return None
    return bytes.fromhex(text)


def _first_line(path: str) -> str:
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return f.readline()
    except OSError as e:
        raise KeyFileError(f"{path}: cannot open: {e.strerror}") from None


def read_secret_key(path: str) -> bytes:
    """The 32-byte secret of a secret key file. Refused when group or others may
    read it (as SSH refuses), or when it is not a key file."""
    try:
        mode = stat.S_IMODE(os.stat(path).st_mode)
    except OSError as e:
        raise KeyFileError(f"{path}: cannot open: {e.strerror}") from None
    if mode & 0o077:
        raise KeyFileError(f"{path}: permissions {mode:04o} let others read this secret key; chmod 600 {path}")
    words = _first_line(path).split()
    secret = parse_key_hex(words[1]) if len(words) >= 2 and words[0] == _SECRET_TAG else None
    if secret is None:
        raise KeyFileError(f"{path}: not a secret key file (expected \"{_SECRET_TAG} <64 hex digits>\")")
    return secret


def read_public_key(path_or_hex: str) -> bytes:
    """A public key: 64 hex digits given directly, or a .pub file."""
    key = parse_key_hex(path_or_hex)
    if key is not None:
        return key
    words = _first_line(path_or_hex).split()
    key = parse_key_hex(words[1]) if len(words) >= 2 and words[0] == _PUBLIC_TAG else None
    if key is None:
        raise KeyFileError(f"{path_or_hex}: not a public key file (expected \"{_PUBLIC_TAG} <64 hex digits> NAME\")")
    return key


def known_nodes_path() -> str:
    """$XDG_CONFIG_HOME/troupe/known_nodes, else ~/.config/troupe/known_nodes
    ("" when neither $XDG_CONFIG_HOME nor $HOME is set)."""
    xdg = os.environ.get("XDG_CONFIG_HOME", "")
    if xdg:
        return os.path.join(xdg, "troupe", "known_nodes")
    home = os.environ.get("HOME", "")
    return os.path.join(home, ".config", "troupe", "known_nodes") if home else ""


def find_known_node(path: str, host_port: str) -> bytes:
    """The key `path` lists for `host_port` ("HOST:PORT", an IPv6 host in
    brackets). Raises KeyFileError when the file or the node is missing (saying
    how to add it) or the node's line is malformed."""
    how = (f"add the line \"{host_port} <the node's key: 64 hex digits>\" to {path}, "
           "or name the key with node_key=")
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            lines = f.readlines()
    except OSError:
        raise KeyFileError(f"no key known for {host_port} (no {path}): {how}") from None
    for number, line in enumerate(lines, start=1):
        words = line.split()
        if not words or words[0].startswith("#") or words[0] != host_port:
            continue
        key = parse_key_hex(words[1]) if len(words) >= 2 else None
        if key is None:
            raise KeyFileError(f"{path}:{number}: the key of {host_port} is not 64 hex digits")
        return key
    raise KeyFileError(f"no key known for {host_port} in {path}: {how}")
