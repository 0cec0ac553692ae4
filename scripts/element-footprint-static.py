#!/usr/bin/env python3
"""What outside its folder names each element, as the tree stands (issue 24 item 2).

    scripts/element-footprint-static.py            # one section per element folder
    scripts/element-footprint-static.py --check    # exit 1 when an element other than the Sky is needed
    scripts/element-footprint-static.py --root DIR # another tree (the tests use a scratch one)

(Also `scripts/element-footprint.sh --static [--check]`.) The history view of the same question
(`scripts/element-footprint.sh`) lists past commits; this one reads the files. For every element
folder skyelements/<name>/ (with a src/ folder; not the registry) it searches every other file of
the tree (build folders, .git and images left out) for the element's headers
(`welkin/elements/<header>` for each header in its include/welkin/elements/), its folder's path
(`skyelements/<name>/`) and its presence macro (`WELKIN_HAS_ELEMENT_<name>`), and sorts each file
that names it into one of:

  needs    code or a build/script line that would break or need editing if the folder went:
           an #include of its header or its path outside a comment, in a file that does not
           test for the element's presence. Must be none for every element but the Sky (the
           elements that read the atmosphere need it; CI's removal step keeps it).
  guarded  code that uses it only where it is present: the file tests WELKIN_HAS_ELEMENT_<name>
           (compiled only where the folder is), asks the registry for it by name
           (elements::findDescriptor("<name>")), or, in CMake/shell, tests the folder's existence.
  cites    code that names it only in comments (e.g. "measured in skyelements/sky/README.md").
  links    documentation (.md and other text) that links to or names its folder; links into an
           absent folder are counted apart by scripts/check-doc-links.py, not broken.

In a git checkout, a folder with no committed file (CI's template step copies
examples/elements/halo into skyelements/ for one build) is reported but not counted by --check:
its origin, the example that uses it and the script that copies it name it by design.

Exit status: 0, or 1 with --check when a committed element other than the Sky is needed outside
its folder, 2 on bad arguments.
"""
import os
import re
import subprocess
import sys

TEXT_SUFFIXES_DOC = {".md", ".txt", ".csv", ".json", ".dox", ".html"}
SKIP_SUFFIXES = {".png", ".jpg", ".jpeg", ".exr", ".hdr", ".tif", ".tiff", ".gif", ".pdf", ".bin",
                 ".dat", ".svg", ".ico", ".zip", ".gz"}
SKIP_DIRS = {".git", "__pycache__", "node_modules"}
ALWAYS_NEEDED = {"sky"}  # read by the other elements' generators and tests (CI keeps it in place)


def usage_error(msg):
    print(f"element-footprint-static.py: {msg}", file=sys.stderr)
    sys.exit(2)


def tree_files(root):
    """The files to search: in a git checkout whose top is root, the tracked ones and the untracked
    ones git does not ignore (a folder copied in for a test counts; build output and logs that
    .gitignore names do not); elsewhere (a scratch tree) every file under root."""
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], capture_output=True,
                             text=True, check=True).stdout.strip()
        if os.path.realpath(top) == os.path.realpath(root):
            listed = subprocess.run(["git", "-C", root, "ls-files", "-z", "--cached", "--others",
                                     "--exclude-standard"], capture_output=True, text=True, check=True).stdout
            for rel in sorted(set(f for f in listed.split("\0") if f)):
                path = os.path.join(root, rel)
                if os.path.isfile(path) and not os.path.islink(path) and \
                        os.path.splitext(rel)[1].lower() not in SKIP_SUFFIXES:
                    yield rel
            return
    except (OSError, subprocess.CalledProcessError):
        pass
    for dirpath, dirnames, filenames in os.walk(root):
        rel = os.path.relpath(dirpath, root)
        top = rel.split(os.sep)[0]
        dirnames[:] = [d for d in dirnames if d not in SKIP_DIRS and not (rel == "." and d.startswith("build"))]
        if top.startswith("build") and rel != ".":
            continue
        for f in filenames:
            path = os.path.join(dirpath, f)
            if os.path.splitext(f)[1].lower() in SKIP_SUFFIXES or os.path.islink(path):
                continue
            yield os.path.relpath(path, root).replace(os.sep, "/")


def comment_start(line, suffix):
    """Index where a comment starts on this line (len(line) when none), by the file's language."""
    stripped = line.lstrip()
    if suffix in {".cpp", ".hpp", ".h", ".cc", ".glsl", ".comp", ".vert", ".frag", ".js"}:
        if stripped.startswith("*") or stripped.startswith("/*"):
            return 0
        i = line.find("//")
        return i if i >= 0 else len(line)
    if suffix in {".sh", ".py", ".cmake", ".txt", ".in", ""} or suffix == ".cmakelists":
        i = line.find("#")
        # "#include" in a shell heredoc is not a comment, but shell scripts rarely hold C code.
        return i if i >= 0 else len(line)
    return len(line)


def tracked_folders(root):
    """In a git checkout whose top is root: the element folders with tracked files (the library's
    elements). None elsewhere (a scratch tree: every folder counts)."""
    try:
        top = subprocess.run(["git", "-C", root, "rev-parse", "--show-toplevel"], capture_output=True,
                             text=True, check=True).stdout.strip()
        if os.path.realpath(top) != os.path.realpath(root):
            return None
        listed = subprocess.run(["git", "-C", root, "ls-files", "-z", "skyelements"], capture_output=True,
                                text=True, check=True).stdout
        return {f.split("/")[1] for f in listed.split("\0") if f.count("/") >= 2}
    except (OSError, subprocess.CalledProcessError):
        return None


def elements(root):
    base = os.path.join(root, "skyelements")
    out = []
    if not os.path.isdir(base):
        return out
    for name in sorted(os.listdir(base)):
        d = os.path.join(base, name)
        if name == "registry" or not os.path.isdir(os.path.join(d, "src")):
            continue
        inc = os.path.join(d, "include", "welkin", "elements")
        headers = sorted(h for h in os.listdir(inc) if h.endswith(".hpp")) if os.path.isdir(inc) else []
        out.append((name, headers))
    return out


def classify(root, files, name, headers):
    folder = f"skyelements/{name}/"
    macro = f"WELKIN_HAS_ELEMENT_{name}"
    path_re = re.compile(r"skyelements/" + re.escape(name) + r"(/|\b(?![-\w]))")
    doc_path_re = re.compile(r"skyelements/" + re.escape(name) + r"/(README\.md|keys\.md|images/)[^\s'\")]*")
    # In a message saying the element is absent ("no skyelements/grid in this build").
    absent_re = re.compile(r"findDescriptor\(\s*\"" + re.escape(name) + r"\"\s*\)")
    header_res = [re.compile(r"welkin/elements/" + re.escape(h) + r"\b") for h in headers]
    result = {"needs": [], "guarded": [], "cites": [], "links": []}
    for rel in files:
        if rel.startswith(folder):
            continue
        try:
            with open(os.path.join(root, rel), encoding="utf-8") as fh:
                text = fh.read()
        except (UnicodeDecodeError, OSError):
            continue
        has_macro = macro in text
        if not (path_re.search(text) or has_macro or any(r.search(text) for r in header_res)):
            continue
        suffix = os.path.splitext(rel)[1].lower()
        if os.path.basename(rel) == "CMakeLists.txt":
            suffix = ".cmakelists"
        if suffix in TEXT_SUFFIXES_DOC and suffix != ".cmakelists":
            result["links"].append(rel)
            continue
        exists_test = re.search(r"EXISTS\s+[^)\n]*" + re.escape(folder.rstrip("/")), text) or \
            re.search(r"\[\s*-[de]\s+[^]\n]*" + re.escape(folder.rstrip("/")), text)
        live = []
        for n, line in enumerate(text.splitlines(), 1):
            cut = comment_start(line, suffix)
            # A path to the element's page, keys table or images inside a string (a key's
            # description, an error message) cites it; it is not read.
            code = doc_path_re.sub("", line[:cut])
            if path_re.search(code) or any(r.search(code) for r in header_res):
                live.append(n)
        if not live:
            result["cites"].append(rel)
        elif has_macro or exists_test or absent_re.search(text):
            result["guarded"].append(rel)
        else:
            result["needs"].append(f"{rel}:{','.join(map(str, live[:4]))}")
    return result


def main(argv):
    check = False
    root = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    args = list(argv)
    while args:
        a = args.pop(0)
        if a == "--check":
            check = True
        elif a == "--root":
            if not args:
                usage_error("--root needs a folder")
            root = args.pop(0)
            if not os.path.isdir(root):
                usage_error(f"--root '{root}': not a folder")
        else:
            usage_error(f"unknown argument '{a}' (accepted: --check, --root DIR)")
    els = elements(root)
    if not els:
        usage_error(f"no element folders under {root}/skyelements")
    files = sorted(tree_files(root))
    tracked = tracked_folders(root)
    bad = 0
    print(f"what outside its folder names each element ({len(els)} elements, {len(files)} files searched)")
    for name, headers in els:
        r = classify(root, files, name, headers)
        needs = r["needs"]
        tag = "needs none" if not needs else f"needed by {len(needs)} file(s)"
        if needs and name in ALWAYS_NEEDED:
            tag += " (the Sky: read by the others, kept by CI's removal step)"
        elif needs and tracked is not None and name not in tracked:
            # A folder copied in and not committed (CI's template step copies
            # examples/elements/halo here): its origin and the scripts that copy it name it.
            tag += " (not committed: a copy, e.g. the template's, not counted by --check)"
        elif needs:
            bad += 1
        print(f"{name}: {tag}; guarded uses {len(r['guarded'])}, cited in comments {len(r['cites'])}, "
              f"linked from docs {len(r['links'])}")
        for f in needs[:12]:
            print(f"  needs    {f}")
        if len(needs) > 12:
            print(f"  ... ({len(needs) - 12} more)")
        for f in r["guarded"]:
            print(f"  guarded  {f}")
    if bad:
        print(f"{bad} element(s) other than the Sky are needed outside their folders")
    return 1 if (check and bad) else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
