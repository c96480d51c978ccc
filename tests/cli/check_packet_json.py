"""Runs `rayscope inspect ... --packet --format json` (the command after this
script's name) for the pixels 86,122 (on the bunny's silhouette in
data/scenes/bunny.json at 320x240) and 121,142 (inside it), and checks the JSON against
itself: the blocks and lanes of the two pixels, each lane's node count and
last step against the steps' lane masks, and the packet's totals."""
import json
import subprocess
import sys


def fail(message):
    print("check_packet_json: " + message)
    sys.exit(1)


run = subprocess.run(sys.argv[1:], capture_output=True, text=True)
if run.returncode != 0:
    fail("the command failed: " + run.stderr)
packets = json.loads(run.stdout)["packets"]
if len(packets) != 2:
    fail("expected 2 packets, got %d" % len(packets))
first, inside = packets
if first["pixel"] != [86, 122] or first["block"] != {"x0": 84, "y0": 120, "x1": 88, "y1": 124}:
    fail("the first packet's pixel or block: %s %s" % (first["pixel"], first["block"]))
if first["lane"] != 10 or first["lanes"][10]["pixel"] != [86, 122]:
    fail("pixel 86,122 is not lane 10")
if first["lanes"][10].get("object") != "bunny":
    fail("lane 10 does not hit the bunny: %s" % first["lanes"][10])
if inside["pixel"] != [121, 142] or inside["lane"] != 9 or inside["block"]["y0"] != 140:
    fail("the second packet: %s" % inside)
for p in packets:
    steps = p["steps"]
    if p["fell_back"] or not steps:
        fail("packet of %s has no walk" % p["pixel"])
    if p["node_visits"] != len(steps):
        fail("node_visits %d, steps %d" % (p["node_visits"], len(steps)))
    if p["active_lanes"] != sum(s["active"] for s in steps):
        fail("active_lanes is not the steps' sum")
    for s in steps:
        if s["active"] != bin(s["lanes"]).count("1"):
            fail("a step's active count is not its lanes'")
    for k, lane in enumerate(p["lanes"]):
        active = [i + 1 for i, s in enumerate(steps) if s["lanes"] >> k & 1]
        if lane["nodes"] != len(active):
            fail("lane %d: %d nodes, active in %d steps" % (k, lane["nodes"], len(active)))
        if lane["left_at_step"] != (active[-1] if active else 0):
            fail("lane %d left at step %d, last active at %s" % (k, lane["left_at_step"], active))
print("check_packet_json: 2 packets, %d and %d steps" % (len(first["steps"]), len(inside["steps"])))
