"""pvbatch: the plugin's panels. (a) The server-manager XML: every property
of every filter in exactly one panel group, groups contiguous (one header
each in the panel), expert knobs advanced and in the Advanced group, array
lists restricted to numeric arrays, everything documented. (b) With the
plugin loaded: the array lists offer numeric arrays and no string array.
(c) The solver's Debug property prints the run's summary as a debug message
and the same numbers are in the output's field data.

Usage: pvbatch test_plugin_panels.py BUILD/Plugin (the server-manager XML as
built, with the shared properties of Plugin/Shared filled in)"""
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

import paraview.simple as pvs
from paraview import servermanager
from vtkmodules.vtkCommonCore import vtkOutputWindow, vtkStringOutputWindow

if len(sys.argv) < 2:
    sys.exit("usage: pvbatch test_plugin_panels.py BUILD/Plugin")
PLUGIN_DIR = sys.argv[1]
XML_FILES = ("GridFreeFilters.xml", "GridFreeApplications.xml", "GridFreeImplicitFunctions.xml")
FILTERS = ("WalkOnSpheresSolver", "WalkOnSpheresStreamTracer", "WalkOnSpheresAdaptiveSampler",
           "MovingLeastSquaresInterpolator", "WalkOnSpheresDenoiser", "MarkBoundaryConditions",
           "WalkOnSpheresHelmholtzDecomposition", "WalkOnSpheresCrossField",
           "WalkOnSpheresDeformation", "WalkOnSpheresDiffusionCurves")
# Expert knobs: hidden in the basic panel, in the Advanced group, wherever present.
EXPERT = ("Epsilon", "EpsilonIsRelative", "MaxSteps", "Seed", "NumberOfThreads",
          "KeepRunningSums", "Debug")
# What the basic panel must offer, wherever present.
BASIC = ("BoundaryValues", "Equation", "WalksPerPoint", "ComputeGradient", "ComputeHessian",
         "ComputeDirectionalDerivative", "Values", "FieldArray", "FrontColor", "BackColor")

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL: " + message)


def documented(element):
    doc = element.find("Documentation")
    return doc is not None and bool((doc.text or "").strip())


def is_property(element):
    return element.tag == "Property" or element.tag.endswith("VectorProperty") \
        or element.tag in ("ProxyProperty", "InputProperty")


# --- (a) the XML --------------------------------------------------------------
seen = {}
for filename in XML_FILES:
    root = ET.parse(os.path.join(PLUGIN_DIR, filename)).getroot()
    for domain in root.iter("ArrayListDomain"):
        check(domain.get("data_type") == "VTK_DATA_ARRAY",
              "%s: an ArrayListDomain (%s) without data_type=\"VTK_DATA_ARRAY\""
              % (filename, domain.get("input_domain_name")))
    for group in root.findall("ProxyGroup"):
        for proxy in group:
            if not proxy.tag.endswith("Proxy"):
                continue
            name = proxy.get("name")
            check(documented(proxy), "%s: proxy %s has no Documentation" % (filename, name))
            for prop in proxy:
                if is_property(prop):
                    check(documented(prop), "%s: %s.%s has no Documentation"
                          % (filename, name, prop.get("name")))
            if proxy.tag == "SourceProxy":
                seen[name] = proxy

check(sorted(seen) == sorted(FILTERS), "filters found: %s" % sorted(seen))
for name, proxy in seen.items():
    # (Information-only properties and those with panel_visibility "never"
    # are not shown in the panel.)
    props = [p for p in proxy if is_property(p) and p.tag != "InputProperty"
             and p.get("information_only") != "1" and p.get("panel_visibility") != "never"]
    by_name = {p.get("name"): p for p in props}
    groups = {}
    member_of = {}
    for group in proxy.findall("PropertyGroup"):
        label = group.get("label")
        check(label not in groups, "%s: two groups labelled %s" % (name, label))
        groups[label] = [p.get("name") for p in group.findall("Property")]
        for member in groups[label]:
            check(member in by_name, "%s: group %s lists unknown property %s"
                  % (name, label, member))
            member_of.setdefault(member, []).append(label)
    for prop_name in by_name:
        check(len(member_of.get(prop_name, [])) == 1, "%s.%s is in groups %s (want exactly one)"
              % (name, prop_name, member_of.get(prop_name, [])))
    # The panel shows properties in XML order with a header where the group
    # changes: a group split in two gets two headers.
    order = [member_of[p.get("name")][0] for p in props if len(member_of.get(p.get("name"), [])) == 1]
    runs = [label for i, label in enumerate(order) if i == 0 or order[i - 1] != label]
    check(len(runs) == len(set(runs)), "%s: groups not contiguous in XML order: %s" % (name, runs))
    for prop_name in EXPERT:
        if prop_name in by_name:
            check(by_name[prop_name].get("panel_visibility") == "advanced",
                  "%s.%s is not panel_visibility=\"advanced\"" % (name, prop_name))
            check(member_of.get(prop_name) == ["Advanced"], "%s.%s is in %s, not Advanced"
                  % (name, prop_name, member_of.get(prop_name)))
    for prop_name in groups.get("Advanced", []):
        check(by_name.get(prop_name) is not None
              and by_name[prop_name].get("panel_visibility") == "advanced",
              "%s.%s is in the Advanced group but shown in the basic panel" % (name, prop_name))
    for prop_name in BASIC:
        if prop_name in by_name:
            check(by_name[prop_name].get("panel_visibility") in (None, "default"),
                  "%s.%s must stay in the basic panel" % (name, prop_name))

# The panel in the order a user fills it in: the problem first (its group
# holds Boundary Values), implicit boundaries and CSG near the end, expert
# knobs last; the source settings only for equations with a source.
for name in ("WalkOnSpheresSolver", "WalkOnSpheresStreamTracer", "WalkOnSpheresAdaptiveSampler"):
    proxy = seen.get(name)
    if proxy is None:
        continue
    shown = [p.get("name") for p in proxy if is_property(p) and p.tag != "InputProperty"]
    check(shown[:2] == ["BoundaryValues", "Equation"],
          "%s: the panel starts with %s, not Boundary Values and Equation" % (name, shown[:2]))
    labels = [g.get("label") for g in proxy.findall("PropertyGroup")]
    check(labels[0] == "Equation" and labels[-1] == "Advanced"
          and labels[-2] == "Implicit Boundary and CSG",
          "%s: groups in the order %s" % (name, labels))
    # The source array and expression also give f of the equation with
    # varying coefficients, whose own properties show for it alone.
    shown_only_for = {"SourceArray": ["1", "2", "4"], "SourceExpression": ["1", "2", "4"],
                      "SourceOperator": ["1", "2"], "SourceSampling": ["1", "2"]}
    for varying in ("DiffusionFromArray", "DiffusionArray", "DiffusionCoefficient",
                    "AbsorptionFromArray", "AbsorptionArray", "AbsorptionCoefficient",
                    "SourceTermFromArray", "CoefficientSmoothing", "DiffusionExpression",
                    "AbsorptionExpression"):
        shown_only_for[varying] = ["4"]
    found = set()
    for prop in proxy:
        if prop.get("name") in shown_only_for:
            found.add(prop.get("name"))
            shown_for = sorted(d.get("value") for d in prop.iter("PropertyWidgetDecorator")
                               if d.get("property") == "Equation")
            check(shown_for == shown_only_for[prop.get("name")],
                  "%s.%s is shown for equations %s, not %s" % (
                      name, prop.get("name"), shown_for, shown_only_for[prop.get("name")]))
    check(found == set(shown_only_for), "%s lacks %s" % (name, set(shown_only_for) - found))
    equations = [e.get("text") for prop in proxy if prop.get("name") == "Equation"
                 for e in prop.iter("Entry")]
    check(equations == ["Laplace", "Poisson", "Screened Poisson", "Biharmonic",
                        "Varying Coefficients"],
          "%s offers the equations %s" % (name, equations))

# Each shared property is defined once in the sources (Plugin/Shared) and
# included where it is used.
source_dir = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "Plugin")
for filename in XML_FILES:
    source = open(os.path.join(source_dir, filename), encoding="utf-8").read()
    for shared in os.listdir(os.path.join(source_dir, "Shared")):
        prop_name = shared[:-len(".xml")]
        check(re.search(r'<\w+Property\s+name="%s"' % prop_name, source) is None
              or prop_name in ("Source", "SourceArray", "SourceExpression"),
              "%s defines %s again instead of including Plugin/Shared/%s"
              % (filename, prop_name, shared))

solver_xml = seen.get("WalkOnSpheresSolver")
if solver_xml is not None:
    labels = [g.get("label") for g in solver_xml.findall("PropertyGroup")]
    for label in ("Equation", "Sampling", "Outputs", "Advanced"):
        check(label in labels, "WalkOnSpheresSolver has no %s group (%s)" % (label, labels))
    for label in ("Solver", "Execution"):
        check(label not in labels, "WalkOnSpheresSolver still has a %s group" % label)
    sampling = [p.get("name") for g in solver_xml.findall("PropertyGroup")
                if g.get("label") == "Sampling" for p in g]
    for prop_name in ("WalksPerPoint", "Refine", "SourceSampling", "BiharmonicStrategy",
                      "NestedWalks", "ControlVariates"):
        check(prop_name in sampling, "WalkOnSpheresSolver.%s is not in Sampling" % prop_name)
    debug = [p for p in solver_xml if p.get("name") == "Debug"]
    check(len(debug) == 1 and debug[0].tag == "IntVectorProperty"
          and debug[0].get("command") == "SetDebug" and debug[0].get("default_values") == "0"
          and debug[0].find("BooleanDomain") is not None,
          "WalkOnSpheresSolver.Debug: an IntVectorProperty, command SetDebug, default 0, boolean")
if not failures:
    print("ok: XML of %d filters: groups, advanced knobs, numeric array lists, documentation"
          % len(seen))
xml_failures = len(failures)

if not hasattr(pvs, "WalkOnSpheresSolver"):
    sys.exit("GridFree plugin not loaded (PV_PLUGIN_PATH)")

# --- (b) array lists: numeric arrays only ----------------------------------------
sphere = pvs.Sphere(Radius=1.0, ThetaResolution=16, PhiResolution=16)
labelled = pvs.ProgrammableFilter(Input=sphere)
labelled.Script = """
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkIntArray, vtkStringArray
source = self.GetInputDataObject(0, 0)
output = self.GetOutputDataObject(0)
output.ShallowCopy(source)

def add(attributes, array, name, components, count, value):
    array.SetName(name)
    array.SetNumberOfComponents(components)
    array.SetNumberOfTuples(count)
    for i in range(count * components):
        array.SetValue(i, value(i))
    attributes.AddArray(array)

points, cells = source.GetNumberOfPoints(), source.GetNumberOfCells()
add(output.GetPointData(), vtkStringArray(), "Label", 1, points, lambda i: "p%d" % i)
add(output.GetPointData(), vtkStringArray(), "Tags", 3, points, lambda i: "t%d" % i)
add(output.GetPointData(), vtkDoubleArray(), "T", 1, points, lambda i: 0.5 * i)
add(output.GetPointData(), vtkIntArray(), "Region", 1, points, lambda i: i % 3)
add(output.GetPointData(), vtkDoubleArray(), "Velocity", 3, points, lambda i: 0.1 * i)
add(output.GetCellData(), vtkStringArray(), "CellLabel", 1, cells, lambda i: "c%d" % i)
add(output.GetCellData(), vtkDoubleArray(), "CellT", 1, cells, lambda i: 1.0 * i)
"""
labelled.UpdatePipeline()
point_names = list(labelled.PointData.keys())
cell_names = list(labelled.CellData.keys())
# Teeth: ParaView does see the string arrays, so an unrestricted list would offer them.
assert "Label" in point_names and "Tags" in point_names, point_names
assert "CellLabel" in cell_names, cell_names

probe = pvs.Plane(Origin=[-0.4, -0.4, 0.1], Point1=[0.4, -0.4, 0.1], Point2=[-0.4, 0.4, 0.1],
                  XResolution=2, YResolution=2)


def offered(proxy, prop_name):
    domain = proxy.GetProperty(prop_name).SMProperty.GetDomain("array_list")
    assert domain is not None, prop_name
    return [domain.GetString(i) for i in range(domain.GetNumberOfStrings())]


STRINGS = {"Label", "Tags", "CellLabel"}
cases = [
    (pvs.WalkOnSpheresSolver(Boundary=labelled, Probe=probe, Source=labelled),
     ("BoundaryValues", "BackBoundaryValues", "LaplacianValues"), {"T", "Region", "CellT"}),
    (pvs.WalkOnSpheresStreamTracer(Boundary=labelled, Seeds=probe),
     ("BoundaryValues",), {"T", "Region", "CellT"}),
    (pvs.WalkOnSpheresAdaptiveSampler(Boundary=labelled, Domain=probe),
     ("BoundaryValues",), {"T", "Region", "CellT"}),
    (pvs.MovingLeastSquaresInterpolator(Input=probe, Source=labelled),
     ("Values",), {"T", "Region", "Velocity"}),
    (pvs.WalkOnSpheresDenoiser(Input=labelled), ("Values",), {"T", "Region", "Velocity"}),
    (pvs.WalkOnSpheresHelmholtzDecomposition(Boundary=sphere, Probe=probe, Field=labelled),
     ("FieldArray",), {"Velocity"}),
    (pvs.WalkOnSpheresDiffusionCurves(Boundary=labelled, Probe=probe, Source=labelled),
     ("FrontColor", "BackColor"), {"T", "Region", "CellT"}),
]
for proxy, prop_names, numeric in cases:
    for prop_name in prop_names:
        names = set(offered(proxy, prop_name))
        label = "%s.%s" % (proxy.GetXMLName(), prop_name)
        check(numeric <= names, "%s offers %s, missing %s" % (label, sorted(names), sorted(numeric - names)))
        check(not names & STRINGS, "%s offers string arrays %s" % (label, sorted(names & STRINGS)))
solver = cases[0][0]
source_names = set(offered(solver, "SourceArray"))
check({"T", "Region"} <= source_names and not source_names & STRINGS,
      "WalkOnSpheresSolver.SourceArray offers %s" % sorted(source_names))
for proxy, _, _ in cases:
    pvs.Delete(proxy)
if len(failures) == xml_failures:
    print("ok: array lists offer the numeric arrays and no string array")

# --- (c) the solver's summary -------------------------------------------------------
boundary = pvs.Calculator(Input=sphere, ResultArrayName="T", Function="coordsX")
# 5 x 4 points, the last two columns outside the sphere (exterior problem:
# some walks escape, so the escaped fraction is neither 0 nor 1).
line_probe = pvs.Plane(Origin=[-0.5, -0.3, 0.1], Point1=[2.5, -0.3, 0.1],
                       Point2=[-0.5, 0.3, 0.1], XResolution=4, YResolution=3)
POINTS, WALKS = 20, 16


def solve(debug):
    """Runs a fresh solver with Debug on or off; returns the output window's
    text and the output."""
    window = vtkStringOutputWindow()
    previous = vtkOutputWindow.GetInstance()  # this reference keeps it alive
    vtkOutputWindow.SetInstance(window)
    try:
        run = pvs.WalkOnSpheresSolver(Boundary=boundary, Probe=line_probe)
        run.BoundaryValues = ["POINTS", "T"]
        run.WalksPerPoint = WALKS
        run.Seed = 3
        run.Debug = debug
        run.UpdatePipeline()
        text = window.GetOutput()
    finally:
        vtkOutputWindow.SetInstance(previous)
    data = servermanager.Fetch(run)
    pvs.Delete(run)
    return text, data


def field(data, name):
    array = data.GetFieldData().GetArray(name)
    assert array is not None, "no field data array %s" % name
    return array.GetTuple1(0)


text, data = solve(1)
check(data.GetNumberOfPoints() == POINTS, "output points: %d" % data.GetNumberOfPoints())
SUMMARY_ARRAYS = ("ProbePoints", "TotalWalks", "SolveSeconds", "WalksPerSecond",
                  "MeanStepsPerWalk", "EscapedWalkFraction", "TotalSteps", "EscapedWalks")
missing = [name for name in SUMMARY_ARRAYS if data.GetFieldData().GetArray(name) is None]
check(not missing, "no field data arrays %s" % missing)
if not missing:
    total = field(data, "TotalWalks")
    seconds = field(data, "SolveSeconds")
    check(field(data, "ProbePoints") == POINTS, "ProbePoints %g" % field(data, "ProbePoints"))
    check(total == POINTS * WALKS, "TotalWalks %g, want %d" % (total, POINTS * WALKS))
    check(field(data, "MeanStepsPerWalk") >= 1.0, "MeanStepsPerWalk %g" % field(data, "MeanStepsPerWalk"))
    check(math.isclose(field(data, "MeanStepsPerWalk"), field(data, "TotalSteps") / total),
          "MeanStepsPerWalk is not TotalSteps / TotalWalks")
    escaped = field(data, "EscapedWalkFraction")
    check(0.0 < escaped < 1.0, "EscapedWalkFraction %g (probe half outside: want in (0, 1))" % escaped)
    check(math.isclose(escaped, field(data, "EscapedWalks") / total),
          "EscapedWalkFraction is not EscapedWalks / TotalWalks")
    check(seconds >= 0.0 and field(data, "WalksPerSecond") > 0.0,
          "SolveSeconds %g, WalksPerSecond %g" % (seconds, field(data, "WalksPerSecond")))
    if seconds > 0.0:
        check(math.isclose(field(data, "WalksPerSecond"), total / seconds, rel_tol=1e-9),
              "WalksPerSecond is not TotalWalks / SolveSeconds")

summaries = [line for line in text.splitlines() if "summary:" in line]
check(len(summaries) == 1, "Debug on: want one summary line, output window had: %r" % text[-2000:])
match = None
if summaries:
    match = re.search(r"summary: (\d+) probe points, (\d+) walks \(\d+ run now\), (\S+) s, (\S+) walks/s, "
                      r"(\S+) steps per walk, escaped fraction (\S+)", summaries[0])
    check(match is not None, "summary line: %r" % summaries[0])
    # A debug message: ParaView lists it in Output Messages.
    check("Debug: In " in text.split("summary:")[0], "the summary is not a debug message: %r" % text)
if match:
    points, walks = int(match.group(1)), int(match.group(2))
    check(points == POINTS and walks == POINTS * WALKS,
          "summary says %d points, %d walks; want %d, %d" % (points, walks, POINTS, POINTS * WALKS))
    if not missing:
        for group, name in ((5, "MeanStepsPerWalk"), (6, "EscapedWalkFraction")):
            printed, stored = float(match.group(group)), field(data, name)
            check(math.isclose(printed, stored, rel_tol=1e-4, abs_tol=1e-12),
                  "summary %s %g, field data %g" % (name, printed, stored))

quiet, data = solve(0)
check(field(data, "TotalWalks") == POINTS * WALKS, "Debug off: the solver did not run")
check("summary:" not in quiet, "Debug off, yet a summary was printed: %r" % quiet[-2000:])

if failures:
    sys.exit("%d check(s) failed" % len(failures))
print("ok: Debug prints the summary (%s), field data consistent, silent with Debug off"
      % (summaries[0].split("summary: ", 1)[1] if summaries else "?"))
