#!/usr/bin/env python3
"""Reads a ZIP with Python's zipfile (an independent reader) for zip_writer_test and the hub's
catalog.zip tests: every entry's CRC-32 checked (testzip), then a JSON report on stdout:
{"count", "names" (in central-directory order), "zip64" (the archive has a zip64 end record),
"data" (name -> bytes in hex, with --data)}. Exit 1 when an entry is damaged."""
import json
import sys
import zipfile

path = sys.argv[1]
with zipfile.ZipFile(path) as z:
    bad = z.testzip()
    if bad is not None:
        print(f"bad CRC or header in {bad}", file=sys.stderr)
        sys.exit(1)
    infos = z.infolist()
    report = {"count": len(infos), "names": [i.filename for i in infos]}
    with open(path, "rb") as f:
        report["zip64"] = b"PK\x06\x06" in f.read()[-200000:]
    if "--data" in sys.argv:
        report["data"] = {i.filename: z.read(i).hex() for i in infos}
print(json.dumps(report))
