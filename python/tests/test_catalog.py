"""``junta.catalog()`` mirrors ``junta list`` (the registry as data) and shows
the laws registered from Python."""

import subprocess

import pytest

import junta
from conftest import PyPenalty, junta_command


def plugins(title):
    for sec in junta.catalog():
        if sec["title"] == title:
            return {p["key"]: p for p in sec["plugins"]}
    raise AssertionError(f"no section {title!r}")


def test_list_has_bilinear_with_its_parameters():
    laws = plugins("interface laws")
    b = laws["bilinear"]
    assert not b["runtime"]
    assert "G_Ic" in b["description"]
    params = {p["name"]: p["doc"] for p in b["params"]}
    assert {"K", "N", "S", "G_Ic", "G_IIc", "eta"} <= set(params)
    assert "mode I toughness" in params["G_Ic"]
    assert "quadratic" in plugins("failure criteria")
    assert {"h8", "h20", "inter18"} <= set(plugins("elements"))
    assert {"cholesky", "ldlt", "cg"} <= set(plugins("linear solvers"))


def test_list_shows_a_law_registered_from_python():
    junta.register_law("py_listed", PyPenalty, description="listed from Python", params={"d": "penalty, N/m^3"})
    try:
        p = plugins("interface laws")["py_listed"]
        assert p["runtime"] and p["description"] == "listed from Python"
        assert p["params"] == [{"name": "d", "doc": "penalty, N/m^3"}]
    finally:
        assert junta.unregister_law("py_listed")
    assert "py_listed" not in plugins("interface laws")
    assert not junta.unregister_law("py_listed")


def test_list_has_every_key_the_cli_lists():
    try:
        out = subprocess.run(junta_command() + ["list"], capture_output=True, text=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired) as e:  # no binary and no cargo
        pytest.skip(f"no junta command line: {e}")
    assert out.returncode == 0, out.stderr
    keys = {p["key"] for sec in junta.catalog() for p in sec["plugins"] if not p["runtime"]}
    # `junta list`: a section title, then `  key  description` lines and
    # `      param  doc` lines
    cli = {line.split()[0] for line in out.stdout.splitlines() if line.startswith("  ") and not line.startswith("      ")}
    assert cli == keys


def test_list_is_a_deprecated_alias_of_catalog():
    with pytest.warns(DeprecationWarning, match=r"junta.catalog\(\)"):
        old = junta.list()
    assert old == junta.catalog()
    assert "list" not in junta.__all__ and "catalog" in junta.__all__
