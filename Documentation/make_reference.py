"""Writes Documentation/Reference.md, the reference of every GridFree filter,
implicit function and property, from the plugin's server-manager XML (the
text ParaView shows in its help and tooltips), so the two never disagree.

    python3 Documentation/make_reference.py build/Plugin            # rewrite Reference.md
    python3 Documentation/make_reference.py build/Plugin --check    # exit 1 if stale

It reads the XML as the build writes it (build/Plugin: the proxies with their
shared properties from Plugin/Shared filled in).

The test Documentation.ReferenceUpToDate runs the check.
"""
import os
import re
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
PLUGIN = None  # the build's Plugin folder, from the command line
XML_FILES = ["GridFreeFilters.xml", "GridFreeApplications.xml", "GridFreeImplicitFunctions.xml"]
PROPERTY_TAGS = ("IntVectorProperty", "DoubleVectorProperty", "StringVectorProperty",
                 "ProxyProperty", "InputProperty", "Property", "IdTypeVectorProperty")


def text(element):
    """An element's Documentation as one paragraph."""
    doc = element.find("Documentation")
    if doc is None or doc.text is None:
        return ""
    return re.sub(r"\s+", " ", doc.text).strip()


def python_name(name, label):
    """The name paraview.simple uses: the label without spaces, else the name."""
    return re.sub(r"[^A-Za-z0-9_]", "", label) if label else name


def default_of(prop):
    """A property's default as the user sees it (enumeration text, on/off)."""
    if prop.tag == "InputProperty":
        optional = prop.find("Hints/Optional") is not None
        types = [d.get("value") for d in prop.findall("DataTypeDomain/DataType")]
        return ("optional; " if optional else "") + ", ".join(types)
    if prop.tag == "ProxyProperty":
        proxies = [p.get("name") for p in prop.findall("ProxyListDomain/Proxy")]
        return "one of " + ", ".join(proxies) if proxies else ""
    if prop.tag == "Property":
        return "button"
    values = prop.get("default_values")
    if prop.find("BooleanDomain") is not None and values is not None:
        return "on" if values.strip() == "1" else "off"
    entries = {e.get("value"): e.get("text") for e in prop.findall("EnumerationDomain/Entry")}
    if entries and values is not None:
        return entries.get(values.strip(), values)
    if prop.find("ArrayListDomain") is not None:
        return "an array of the input"
    if values is None:
        return ""
    return values if values.strip() else "(empty)"


def choices_of(prop):
    entries = [e.get("text") for e in prop.findall("EnumerationDomain/Entry")]
    if entries:
        return "Choices: " + ", ".join(entries) + "."
    rng = prop.find("DoubleRangeDomain") or prop.find("IntRangeDomain")
    if rng is not None and rng.get("min") and rng.get("max"):
        return "Range: %s to %s." % (rng.get("min"), rng.get("max"))
    if rng is not None and rng.get("min"):
        return "At least %s." % rng.get("min")
    if rng is not None and rng.get("max"):
        return "At most %s." % rng.get("max")
    return ""


def proxy_section(proxy):
    label = proxy.get("label") or proxy.get("name")
    lines = ["### %s" % label, ""]
    lines.append("`%s` (C++/Python class `%s`), in paraview.simple `%s(...)`."
                 % (proxy.get("name"), proxy.get("class"), python_name(proxy.get("name"), label)))
    lines.append("")
    doc = proxy.find("Documentation")
    if doc is not None and doc.get("short_help"):
        lines += [doc.get("short_help"), ""]
    if text(proxy):
        lines += [text(proxy), ""]
    props = [p for p in proxy if p.tag in PROPERTY_TAGS and p.get("name")]
    if not props:
        return lines
    by_name = {p.get("name"): p for p in props}
    # Properties in panel order: inputs, then each group, then the rest.
    ordered, seen = [], set()
    for p in props:
        if p.tag == "InputProperty":
            ordered.append(("Inputs", p))
            seen.add(p.get("name"))
    for g in proxy.findall("PropertyGroup"):
        for member in g.findall("Property"):
            name = member.get("name")
            if name in by_name and name not in seen:
                ordered.append((g.get("label") or "", by_name[name]))
                seen.add(name)
    for p in props:
        if p.get("name") not in seen and p.get("panel_visibility") != "never":
            ordered.append(("Other", p))
    lines += ["| Group | Property (Python name) | Default | Description |", "|---|---|---|---|"]
    for group_label, p in ordered:
        if p.get("panel_visibility") == "never":
            continue
        name = python_name(p.get("name"), p.get("label"))
        shown = p.get("label") or p.get("name")
        advanced = " (advanced)" if p.get("panel_visibility") == "advanced" else ""
        description = " ".join(x for x in (text(p), choices_of(p)) if x)
        lines.append("| %s | %s (`%s`)%s | %s | %s |" % (
            group_label, shown, name, advanced, default_of(p).replace("|", "\\|"),
            description.replace("|", "\\|")))
    lines.append("")
    return lines


def reference():
    out = ["# GridFree reference: filters, implicit functions and properties", "",
           "Generated by `Documentation/make_reference.py` from the plugin's XML",
           "(`Plugin/*.xml`), the same text ParaView shows in its help and tooltips.",
           "Properties marked *advanced* show in ParaView's panel after the gear",
           "button (or a search). In Python, `paraview.simple` takes the names in",
           "brackets; the C++/Python classes have `Set<Name>` methods, and array",
           "selections are `SetInputArrayToProcess` calls.", ""]
    sections = {"filters": [], "implicit_functions": []}
    for name in XML_FILES:
        root = ET.parse(os.path.join(PLUGIN, name)).getroot()
        for group in root.findall("ProxyGroup"):
            for proxy in group:
                if proxy.tag in ("SourceProxy", "Proxy") and proxy.get("class"):
                    sections.setdefault(group.get("name"), []).append(
                        proxy_section(proxy))
    out += ["## Filters (menu Filters > GridFree)", ""]
    for lines in sections["filters"]:
        out += lines
    out += ["## Implicit functions (Implicit Boundary of the solver)", ""]
    for lines in sections["implicit_functions"]:
        out += lines
    return "\n".join(out).rstrip() + "\n"


def main():
    global PLUGIN
    folders = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(folders) != 1 or not os.path.isfile(os.path.join(folders[0], XML_FILES[0])):
        sys.exit("usage: make_reference.py BUILD/Plugin [--check] (the folder with the built "
                 + XML_FILES[0] + ")")
    PLUGIN = folders[0]
    target = os.path.join(HERE, "Reference.md")
    content = reference()
    if "--check" in sys.argv:
        current = open(target, encoding="utf-8").read() if os.path.exists(target) else ""
        if current != content:
            sys.exit("Documentation/Reference.md is stale: run python3 Documentation/make_reference.py BUILD/Plugin")
        print("ok: Documentation/Reference.md matches the plugin's XML")
        return
    with open(target, "w", encoding="utf-8") as f:
        f.write(content)
    print("wrote", target)


if __name__ == "__main__":
    main()
