#!/usr/bin/env bash
# Checks the workspace's layering rules (docs/architecture.md, "Rules") over the repository and names each
# violation as "<rule>: <file>[:<line>]: <what>". Exit 0: no violation; 1: violations; 2: usage error.
#   scripts/check_layers.sh [--root DIR] [--rule NAME]... [--list-rules] [--help]
# Debian's /usr/bin/python3 alone: reads sources, CMakeLists.txt (+ included .cmake) and package.xml; about 1 s.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export CHECK_LAYERS_DEFAULT_ROOT="$(cd "$here/.." && pwd)"
exec /usr/bin/python3 - "$@" <<'PYTHON'
import argparse, os, re, subprocess, sys
from types import SimpleNamespace
from collections import defaultdict

RULES = {
    "core-includes": "core files (include/<pkg>/, src/ outside the adapter and fixture folders) include no ROS "
                     "header, no generated message header, no adapter header",
    "core-links": "core library targets link no ${catkin_LIBRARIES} or ${<catkin package>_LIBRARIES} and hold "
                  "core sources only",
    "node-location": "every file with main() that starts ROS (ros::init, runNode) lives in src/nodes/ "
                     "(bench/ and test/ for benchmarks and tests)",
    "fixtures": "fixtures and synthetic-data generators live in testing/ folders, are built into *_testing "
                "libraries only, and no node links a *_testing library",
    "package-arrows": "an application (thorvald_navigation, greenhouse_rail_nav, cotton_harvester) does not "
                      "depend on the simulator or on bringup (package.xml, CMake outside tests)",
    "command-line": "no program calls CLI11_PARSE or CLI::App::exit itself (thorvald_common/command_line.h does)",
}
APPLICATIONS = {"thorvald_navigation", "greenhouse_rail_nav", "cotton_harvester"}
TOP_LAYER = {"thorvald_sim", "thorvald_bringup", "cotton_harvester_sim"}
ADAPTER_DIRS = ("src/nodes/", "src/ros/", "src/plugins/")
CPP = re.compile(r"\.(h|hh|hpp|c|cc|cpp|cxx)$")
ROS_INCLUDE_ROOTS = {
    "ros", "rosbag", "rosconsole", "roscpp", "rostest", "tf", "tf2_ros", "tf2_eigen", "tf2_geometry_msgs",
    "pluginlib", "class_loader", "actionlib", "diagnostic_updater", "image_transport", "cv_bridge",
    "pcl_conversions", "pcl_ros", "message_filters", "nodelet", "dynamic_reconfigure", "urdf", "xmlrpcpp",
    "laser_geometry", "kdl_parser", "XmlRpc.h", "XmlRpcValue.h", "XmlRpcException.h"}
NON_CATKIN_VARS = {"OpenCV", "PCL", "EIGEN3", "Eigen3", "Boost", "urdfdom", "YAML_CPP", "GTEST", "GMOCK",
                   "OSMESA", "GL", "CMAKE_THREAD", "CMAKE_DL", "mujoco", "TINYXML2", "console_bridge"}

def parse_args(argv):
    """argparse: --help exits 0, a usage error exits 2 (the workspace's command-line convention)."""
    ap = argparse.ArgumentParser(prog="check_layers.sh", description="Checks the layering rules of "
                                 "docs/architecture.md; exit 0 clean, 1 violations, 2 usage error.")
    ap.add_argument("--root", default=os.environ["CHECK_LAYERS_DEFAULT_ROOT"], help="repository to check")
    ap.add_argument("--rule", action="append", choices=list(RULES), help="check only this rule (repeatable)")
    ap.add_argument("--list-rules", action="store_true", help="print the rules and exit")
    args = ap.parse_args(argv)
    if args.list_rules:
        print("\n".join(f"{name}: {text}" for name, text in RULES.items()))
        sys.exit(0)
    if not os.path.isdir(args.root):
        ap.error(f"no folder {args.root}")
    return os.path.abspath(args.root), set(args.rule or RULES)

def list_files(root):
    """Tracked and untracked-but-not-ignored files in a git checkout; every file outside hidden folders else."""
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], capture_output=True,
                             text=True, check=True).stdout.strip()
        if os.path.realpath(top) == os.path.realpath(root):
            out = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                                  "--exclude-standard"], capture_output=True, text=True, check=True).stdout
            return sorted({f for f in out.split("\0") if f and os.path.isfile(os.path.join(root, f))})
    except (OSError, subprocess.CalledProcessError):
        pass
    found = []
    for d, dirs, files in os.walk(root):
        dirs[:] = [x for x in dirs if x[0] != "." and not os.path.exists(os.path.join(d, x, "CATKIN_IGNORE"))]
        found += [os.path.relpath(os.path.join(d, f), root) for f in files]
    return sorted(found)

def read(root, rel):
    with open(os.path.join(root, rel), encoding="utf-8", errors="replace") as f:
        return f.read()

def strip_cpp_comments(text):
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)

# ---- CMake: commands with foreach/set expansion, testing blocks, included .cmake files ------------------------
def cmake_commands(text):
    """(command, arguments, line) of each top-level command; quoted parentheses do not count."""
    text, pos = re.sub(r"#[^\n]*", "", text), 0  # no '#' inside quoted arguments in this workspace
    while m := re.compile(r"\b([A-Za-z_]\w*)\s*\(").search(text, pos):
        depth, j, quoted = 1, m.end(), False
        while j < len(text) and depth:
            quoted ^= text[j] == '"' and text[j - 1] != "\\"
            depth += 0 if quoted else {"(": 1, ")": -1}.get(text[j], 0)
            j += 1
        yield m.group(1).lower(), re.findall(r'"[^"]*"|[^\s"]+', text[m.end():j - 1]), text.count("\n", 0, m.start()) + 1
        pos = j

def expand(words, env):
    out = []
    for w in words:
        w = w.strip('"')
        for _ in range(3):
            w = re.sub(r"\$\{(\w+)\}", lambda m: env[m.group(1)] if m.group(1) in env else m.group(0), w)
        out += w.split(";") if ";" in w else w.split()
    return [w for w in out if w]

def parse_cmake(root, pkg, rel, env):
    run_cmake_block(root, pkg, rel, list(cmake_commands(read(root, rel))), env, [])

def run_cmake_block(root, pkg, rel, cmds, env, ifs):
    i = 0
    while i < len(cmds):
        name, args, line = cmds[i]
        if name == "foreach":
            depth, j = 1, i + 1
            while depth:
                depth += {"foreach": 1, "endforeach": -1}.get(cmds[j][0], 0)
                j += 1
            items = expand(args[1:], env)
            items = items[1:] if items and items[0] in ("IN", "ITEMS", "LISTS") else items
            for item in items:
                run_cmake_block(root, pkg, rel, cmds[i + 1:j - 1], dict(env, **{args[0]: item}), ifs)
            i = j
            continue
        if name == "if":
            ifs = ifs + [" ".join(args)]
        elif name == "endif":
            ifs = ifs[:-1]
        else:
            cmake_command(root, pkg, rel, name, args, line, env, any("CATKIN_ENABLE_TESTING" in c for c in ifs))
        i += 1

def cmake_command(root, pkg, rel, name, args, line, env, testing):
    words = expand(args, env)
    if name == "set" and words:
        env[words[0]] = ";".join(w for w in words[1:] if w not in ("CACHE", "PARENT_SCOPE"))
    elif name == "list" and words[:1] == ["FILTER"] and len(words) > 1:
        env[words[1]] = "${" + words[1] + "}"  # a filtered list: what it holds is not known here
    elif name == "include" and words and words[0].endswith(".cmake"):
        for inc in (os.path.normpath(words[0]), os.path.normpath(os.path.join(os.path.dirname(rel), words[0]))):
            if os.path.isfile(os.path.join(root, inc)):
                parse_cmake(root, pkg, inc, env)
                break
    elif name in ("add_library", "add_executable", "catkin_add_gtest", "catkin_add_gmock", "add_rostest_gtest"):
        kind = "library" if name == "add_library" else "executable"
        srcs = [w for w in words[1:] if re.search(r"\.(c|cc|cpp|cxx)$", w)]
        pkg.targets[words[0]] = dict(kind=kind, sources=[src_path(pkg, s) for s in srcs], links=[], line=line,
                                     testing=testing or name != "add_executable" and kind != "library", file=rel)
    elif name == "target_sources" and words and words[0] in pkg.targets:
        pkg.targets[words[0]]["sources"] += [src_path(pkg, s) for s in words[1:] if "." in s]
    elif name == "target_link_libraries" and words and words[0] in pkg.targets:
        pkg.targets[words[0]]["links"] += [(w, rel, line) for w in words[1:]
                                           if w not in ("PUBLIC", "PRIVATE", "INTERFACE")]
    elif name == "catkin_package":
        section, pkg.export_where = None, f"{rel}:{line}"
        for w in words:
            if w.isupper():
                section = w
            else:
                {"LIBRARIES": pkg.exported, "CATKIN_DEPENDS": pkg.catkin_depends}.get(section, []).append(w)
    elif name == "find_package" and words:
        if words[0] == "catkin" and "COMPONENTS" in words:
            comps = words[words.index("COMPONENTS") + 1:]
            pkg.components += comps
            pkg.found += [(c, rel, line, testing) for c in comps]
        else:
            pkg.found.append((words[0], rel, line, testing))

def src_path(pkg, s):
    return os.path.normpath(s if s.startswith(pkg.path + "/") else os.path.join(pkg.path, s))

# ---- The repository model -----------------------------------------------------------------------------------
def load_packages(root, files):
    """{name: package}: path, targets {name: dict(kind, sources, links, line, testing, file)}, exported (catkin_package
    LIBRARIES, at export_where), catkin_depends, components (find_package(catkin COMPONENTS)), found (find_package)."""
    pkgs = {}
    for f in (f for f in files if os.path.basename(f) == "package.xml"):
        m = re.search(r"<name>\s*([\w-]+)\s*</name>", read(root, f))
        if m:
            pkgs[m.group(1)] = SimpleNamespace(name=m.group(1), path=os.path.dirname(f), targets={}, exported=[],
                                               export_where="", catkin_depends=[], components=[], found=[])
    for pkg in pkgs.values():
        cm = os.path.join(pkg.path, "CMakeLists.txt")
        if os.path.isfile(os.path.join(root, cm)):
            parse_cmake(root, pkg, cm, {"PROJECT_NAME": pkg.name, "CMAKE_CURRENT_SOURCE_DIR": pkg.path,
                                        "PROJECT_SOURCE_DIR": pkg.path})
    return pkgs

def package_of(pkgs, f):
    return max((p for p in pkgs.values() if f.startswith(p.path + "/")), key=lambda p: len(p.path), default=None)

def classify(pkg, f):
    """'core', 'adapter', 'fixture' or None (tests, benches, tools) for a C/C++ file of `pkg`."""
    rel = f[len(pkg.path) + 1:]
    if not CPP.search(rel):
        return None
    if re.match(r"include/[^/]+/testing/|src/testing/", rel):
        return "fixture"
    if re.match(r"include/[^/]+/ros/", rel) or rel.startswith(ADAPTER_DIRS):
        return "adapter"
    if rel.startswith(("include/", "src/")):
        return "core"
    return None

def generated_headers(owners):
    """The headers catkin generates from the workspace's msg/, srv/ and action/ files."""
    heads, suffixes = set(), {"msg": [""], "srv": ["", "Request", "Response"], "action": [
        "Action", "Goal", "Result", "Feedback", "ActionGoal", "ActionResult", "ActionFeedback"]}
    for f, p in owners.items():
        m = re.match(r"(msg|srv|action)/(\w+)\.(msg|srv|action)$", f[len(p.path) + 1:]) if p else None
        heads |= {f"{p.name}/{m.group(2)}{e}.h" for e in suffixes[m.group(1)]} if m else set()
    return heads

# ---- The rules ------------------------------------------------------------------------------------------------
def include_lines(text):
    for n, line in enumerate(strip_cpp_comments(text).split("\n"), 1):
        if m := re.match(r'\s*#\s*include\s*([<"])([^>"]+)[>"]', line):
            yield n, m.group(1), m.group(2)

def header_layer(root, pkgs, f, quote, inc):
    """Layer ('adapter', 'fixture', 'core') of a workspace header named by an include line, or None."""
    cands = [os.path.normpath(os.path.join(os.path.dirname(f), inc))] if quote == '"' else []
    first = inc.split("/")[0]
    if first in pkgs:
        cands.append(os.path.join(pkgs[first].path, "include", inc))
        if re.match(r"[^/]+/ros/", inc):
            return "adapter"
        if re.match(r"[^/]+/testing/", inc):
            return "fixture"
    for c in cands:
        owner = package_of(pkgs, c)
        if owner and os.path.isfile(os.path.join(root, c)):
            return classify(owner, c)
    return None

def ros_header(inc, generated):
    first = inc.split("/")[0]
    return inc in generated or first in ROS_INCLUDE_ROOTS or bool(re.search(r"_(msgs|srvs)$", first)) or \
        (first == "tf2" and not inc.startswith("tf2/LinearMath/"))

def check_includes(root, files, pkgs, layer_of, generated, report):
    for f, (pkg, layer) in layer_of.items():
        bad = []
        for n, quote, inc in include_lines(read(root, f)):
            target = header_layer(root, pkgs, f, quote, inc)
            if target == "fixture" and layer != "fixture":
                report("fixtures", f"{f}:{n}", f"{layer} file includes fixture header {inc}")
            if layer == "core" and (ros_header(inc, generated) or target == "adapter"):
                bad.append((n, inc))
        if bad:
            report("core-includes", f"{f}:{bad[0][0]}", "core file includes ROS or adapter headers: " +
                   ", ".join(inc for _, inc in bad))

def catkin_var(word):
    m = re.fullmatch(r"\$\{(\w+)_(LIBRARIES|LIBS)\}", word)
    return m.group(1) if m and m.group(1) not in NON_CATKIN_VARS else None

def check_libraries(pkg, report):
    layer = classify
    for name, t in pkg.targets.items():
        layers = {layer(pkg, s) for s in t["sources"]}
        where = f"{t['file']}:{t['line']}"
        if t["kind"] == "library" and name.endswith("_testing"):
            for s in t["sources"]:
                if layer(pkg, s) != "fixture":
                    report("fixtures", where, f"fixture library {name} builds {s} outside a testing/ folder")
            continue
        for s in t["sources"]:
            if layer(pkg, s) == "fixture" and (t["kind"] == "library" or is_node(t)):
                report("fixtures", where, f"{t['kind']} {name} builds fixture source {s}")
        if t["kind"] != "library" or "core" not in layers:
            continue
        if layers & {"adapter"}:
            report("core-links", where, f"library {name} mixes core sources with ROS adapter sources")
        for word, rel, line in t["links"]:
            if catkin_var(word):
                report("core-links", f"{rel}:{line}", f"core library {name} links {word}")

def is_node(t):  # a program built from src/ whose main() starts ROS (check_nodes sets starts_ros)
    return t["kind"] == "executable" and not t["testing"] and t.get("starts_ros", False)

def link_closure(pkgs, pkg, target_name):
    """Every library a target links, directly or through catkin variables: {library: chain}."""
    owner_of = {n: p for p in pkgs.values() for n in p.targets}
    seen, todo = {}, [(pkg, target_name, target_name)]
    while todo:
        p, name, chain = todo.pop()
        t = p.targets.get(name)
        for word, _, _ in (t["links"] if t else []):
            for lib, via in expand_link(pkgs, p, word):
                if lib not in seen:
                    seen[lib] = f"{chain} -> {via}{lib}"
                    if lib in owner_of:
                        todo.append((owner_of[lib], lib, seen[lib]))
    return seen

def expand_link(pkgs, pkg, word):
    var = catkin_var(word)
    if var is None:
        return [(word, "")]
    roots = [c for c in pkg.components if c in pkgs] if var == "catkin" else [var] if var in pkgs else []
    out, stack, done = [], list(roots), set()
    while stack:
        q = stack.pop()
        if q in done:
            continue
        done.add(q)
        out += [(lib, f"{word} ({q} exports) ") for lib in pkgs[q].exported]
        stack += [d for d in pkgs[q].catkin_depends if d in pkgs]
    return out

def check_nodes(root, files, pkgs, layer_of, report):
    main_re = re.compile(r"\bint\s+main\s*\(")
    ros_re = re.compile(r"\bros::init\s*\(|\brunNode\s*[<(]")
    starts_ros = set()
    for f in files:
        if not re.search(r"\.(c|cc|cpp|cxx)$", f):
            continue
        text = strip_cpp_comments(read(root, f))
        if main_re.search(text) and ros_re.search(text):
            starts_ros.add(f)
            p = package_of(pkgs, f)
            rel = f[len(p.path) + 1:] if p else f
            if not rel.startswith(("src/nodes/", "bench/", "test/")):
                report("node-location", f, "main() starts ROS outside src/nodes/ (bench/, test/)")
    exported = defaultdict(set)  # (package, fixture library) -> nodes that link it through catkin variables
    for p in pkgs.values():
        for name, t in p.targets.items():
            t["starts_ros"] = bool(set(t["sources"]) & starts_ros) and \
                all(s.startswith(p.path + "/src/") for s in t["sources"])
            if not is_node(t):
                continue
            for lib, chain in sorted(link_closure(pkgs, p, name).items()):
                m = re.search(r"\((\w+) exports\) " + re.escape(lib) + "$", chain)
                if lib.endswith("_testing") and m:
                    exported[(m.group(1), lib)].add(name)
                elif lib.endswith("_testing"):
                    report("fixtures", f"{t['file']}:{t['line']}", f"node {name} links {lib}: {chain}")
    for (owner, lib), nodes in sorted(exported.items()):
        report("fixtures", pkgs[owner].export_where,
               f"catkin_package(LIBRARIES) of {owner} exports {lib}, so {len(nodes)} node(s) link it through "
               f"${{catkin_LIBRARIES}} or ${{{owner}_LIBRARIES}}: " + ", ".join(sorted(nodes)))

def check_generators(layer_of, report):
    for f, (_, layer) in layer_of.items():
        if layer != "fixture" and re.match(r"(synthetic|fake|mock|fixture)_", os.path.basename(f)):
            report("fixtures", f, f"fixture or generator outside a testing/ folder ({layer} file)")

def check_arrows(root, pkgs, report):
    for name in sorted(APPLICATIONS & set(pkgs)):
        p = pkgs[name]
        xml = os.path.join(p.path, "package.xml")
        for n, line in enumerate(read(root, xml).split("\n"), 1):
            m = re.search(r"<(depend|build_depend|build_export_depend|exec_depend|run_depend)>\s*([\w-]+)\s*<", line)
            if m and m.group(2) in TOP_LAYER:
                report("package-arrows", f"{xml}:{n}", f"application {name} has <{m.group(1)}> on {m.group(2)}")
        for dep, rel, line, testing in p.found:
            if dep in TOP_LAYER and not testing:
                report("package-arrows", f"{rel}:{line}", f"application {name} finds {dep} outside its tests")

def check_command_lines(root, files, pkgs, report):
    exe_sources = {s for p in pkgs.values() for t in p.targets.values() if t["kind"] == "executable"
                   for s in t["sources"]}
    for f in files:
        if not CPP.search(f):
            continue
        text = strip_cpp_comments(read(root, f))
        if f not in exe_sources and not re.search(r"\bint\s+main\s*\(", text):
            continue
        for n, line in enumerate(text.split("\n"), 1):
            if "CLI11_PARSE" in line or ("CLI::" in text and re.search(r"\.\s*exit\s*\(", line)):
                report("command-line", f"{f}:{n}", "parses its command line itself: use "
                       "thorvald_common::parseCommandLine (--help exits 0, a usage error 2)")

def main():
    root, rules = parse_args(sys.argv[1:])
    files = list_files(root)
    pkgs = load_packages(root, files)
    found = []

    def report(rule, where, what):
        if rule in rules:
            found.append((rule, where, what))

    owners = {f: package_of(pkgs, f) for f in files}
    layer_of = {f: (p, classify(p, f)) for f, p in owners.items() if p and classify(p, f)}
    check_includes(root, files, pkgs, layer_of, generated_headers(owners), report)
    check_nodes(root, files, pkgs, layer_of, report)
    for p in pkgs.values():
        check_libraries(p, report)
    check_generators(layer_of, report)
    check_arrows(root, pkgs, report)
    check_command_lines(root, files, pkgs, report)
    counts = defaultdict(int)
    for rule, where, what in sorted(set(found)):
        counts[rule] += 1
        print(f"{rule}: {where}: {what}")
    if found:
        print("check_layers: " + ", ".join(f"{r} {counts[r]}" for r in RULES if counts[r]) + " violation(s)")
        return 1
    print(f"check_layers: ok ({len(rules)} rule(s), {len(pkgs)} packages)")
    return 0

sys.exit(main())
PYTHON
