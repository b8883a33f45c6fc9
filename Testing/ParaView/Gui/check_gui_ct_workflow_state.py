"""Checks the state saved by ct_workflow_apply.xml after the CT workflow was
opened by script and the slice moved by clicks: the solver still solves for
T (Boundary Values), with f as Source Array, the Stream Tracer still traces
T_Gradient (Vectors), and the Slice is at z = 60. Before the script updated
each filter's inputs first, the first Apply wrote '' into the first two and
the streamlines had no points.

    python3 check_gui_ct_workflow_state.py ct_workflow.pvsm"""
import sys
import xml.etree.ElementTree as ET

root = ET.parse(sys.argv[1]).getroot()


def element(proxy_type, prop, index):
    for proxy in root.iter("Proxy"):
        if proxy.get("type") != proxy_type:
            continue
        for p in proxy.iter("Property"):
            if p.get("name") == prop:
                for e in p.iter("Element"):
                    if e.get("index") == str(index):
                        return e.get("value")
    raise AssertionError("no %s.%s[%d] in the state" % (proxy_type, prop, index))


checks = [(("WalkOnSpheresSolver", "BoundaryValues", 4), "T"),
          (("WalkOnSpheresSolver", "SourceArray", 4), "f"),
          (("ArbitrarySourceStreamTracer", "SelectInputVectors", 4), "T_Gradient")]
for (proxy_type, prop, index), want in checks:
    got = element(proxy_type, prop, index)
    assert got == want, (proxy_type, prop, got, want)
z = float(element("Plane", "Origin", 2))
assert z == 60.0, z
print("ok: after the first Apply of the scripted CT workflow the solver solves for T with "
      "source f, the tracer traces T_Gradient, and the slice is at z = 60")
