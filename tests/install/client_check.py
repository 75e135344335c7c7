"""client_check.py HOST PORT: the installed Python client (whatever
PYTHONPATH points at) lists a node's devices and reads position2d:0.
Prints the package's folder and "devices=N x=X"."""
import sys

import troupe

client = troupe.Client(sys.argv[1], int(sys.argv[2]), name="install-check")
if not client.connect():
    raise SystemExit(client.error)
devices = client.device_list() or []
base = troupe.Position2dProxy(client)
got = False
for _ in range(50):  # at most 5 s: a bound against a hang
    client.spin_once(0.1)
    if base.fresh():
        got = True
        break
print(troupe.__file__)
print("devices=%d x=%.3f data=%s" % (len(devices), base.x, got))
sys.exit(0 if devices and got else 1)
