"""gonio.read + info()/summary() over every file of ../shared/corpus against
`gonio info --json` on the same file: the same numbers (exactly: both are
the same JSON object, one printed and parsed, one handed to Python), and
for a file the command refuses, the same error (label `python`)."""
import json
import math

import pytest

import gonio
from conftest import run_gonio


def corpus_files(corpus):
    return sorted(p for p in corpus.rglob("*") if p.is_file() and p.suffix.lower() != ".md")


def same(a, b, where=""):
    """Equal as JSON values; a float that printed and parsed back is the
    same double (nlohmann writes 17 significant digits)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and list(a) == list(b), where
        for k in a:
            same(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{where}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert float(a) == float(b) or (math.isnan(a) and math.isnan(b)), (where, a, b)
    else:
        assert a == b, (where, a, b)


def test_every_corpus_file_gives_the_commands_numbers(corpus, gonio_exe):
    files = corpus_files(corpus)
    assert len(files) >= 100
    read = refused = 0
    for path in files:
        code, out, err = run_gonio(gonio_exe, "info", "--json", path)
        if code != 0:
            with pytest.raises(gonio.GonioError) as caught:
                gonio.read_all(path)
            assert f"gonio: {caught.value}" in err, path
            refused += 1
            continue
        expected = json.loads(out)
        # A GLDF container: {file, format, photometries: [one object each]}.
        expected = expected["photometries"] if "photometries" in expected else [expected]
        photometries = gonio.read_all(path)
        same([p.info() for p in photometries], expected, str(path))
        # summary() is info's summary block, key for key.
        for p, e in zip(photometries, expected):
            for key, value in p.summary().items():
                same(value, e[key], f"{path}:{key}")
        read += 1
    print(f"{read} files gave the command's numbers; {refused} refused with its message")
    assert read >= 100
