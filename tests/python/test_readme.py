"""The README's Python section says what the package does: its worked
example on the real Chiaro export prints what the README shows, and its
lines on the demo's joint fit print what their comments say."""
import os
import re
import subprocess
import sys

from conftest import TOP


def section():
    text = open(os.path.join(TOP, "README.md"), encoding="utf-8").read()
    return text[text.index("\n## Python\n"):text.index("\n## Exit status\n")]


def blocks(text):
    """The indented code blocks, in order."""
    out, cur = [], []
    for line in text.split("\n"):
        if line.startswith("    ") or (cur and line == ""):
            cur.append(line[4:])
        elif cur:
            out.append("\n".join(cur).strip("\n"))
            cur = []
    return out


def python(code):
    p = subprocess.run([sys.executable, "-W", "ignore", "-c", code], cwd=TOP,
                       capture_output=True, env=os.environ)
    assert p.returncode == 0, p.stderr.decode()
    return p.stdout.decode()


def test_real_export_example(realdata):
    b = blocks(section())
    i = next(k for k, x in enumerate(b) if x.startswith("import layerfit"))
    assert python(b[i]).strip() == b[i + 1].strip()


def test_demo_example():
    code = next(x for x in blocks(section()) if 'layerfit.fit("datasets/demo/plan.csv")' in x)
    got = python("import layerfit\n" + code).strip().split("\n")
    want = [m.group(1).strip() for m in re.finditer(r"# (.*)$", code, re.M)]
    # each commented print: its first line is the comment (the loop's "..."
    # stands for the other curves; to_dict() prints nothing)
    assert got[:3] == want[:3]
    assert got[3] == want[3].replace(", ...", "")
