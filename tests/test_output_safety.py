"""Nothing is written outside the output folder, and nothing but a regular file is ever replaced (issue 22, 1).

For every command that writes: hostile names (``../``, an absolute path, NUL, a newline, 300
characters) in the names that become file names, an output folder whose sub-folder is a symbolic
link elsewhere, an output folder that is itself a link (followed: the user named it), and device
nodes and FIFOs in place of an output file. Each refusal is one line, exit 2, and comes before the
command's work (so these tests are fast); the device node is still a character device afterwards.
"""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path

import pytest

from csuas import cli
from csuas.base.errors import ParameterError
from csuas.base.fileio import atomic_path, write_text_atomic
from csuas.base.paths import MAX_NAME_CHARS, file_name_part, inside, output_file, refuse_special

#: Names that must never become part of a file name (the issue's list), by what they try.
HOSTILE = {
    "dotdot": "../../ESC",
    "absolute": "/ABSOLUTE/ESC",  # replaced by a folder under tmp_path in each test
    "nul": "a\0b",
    "newline": "a\nb",
    "long": "x" * 300,
}


def _hostile(kind: str, tmp_path: Path) -> str:
    return str(tmp_path / "abs" / "ESC") if kind == "absolute" else HOSTILE[kind]


def _toml(value: str) -> str:
    """A TOML basic string of ``value`` (JSON's escapes are TOML's)."""
    return json.dumps(value)


def _files(root: Path) -> set:
    return {p for p in root.rglob("*") if not p.is_dir()}


def _run(argv, capsys) -> tuple[int, list[str]]:
    code = cli.main([str(a) for a in argv])
    return code, capsys.readouterr().err.strip().splitlines()


def _refused(argv, capsys, tmp_path: Path, out: Path, *words: str) -> list[str]:
    """Run ``argv``; assert exit 2, one line naming ``words``, nothing written anywhere but ``out``."""
    before = _files(tmp_path)
    code, err = _run(argv, capsys)
    assert code == 2, err
    assert len(err) == 1, err
    for word in words:
        assert word in err[0], err
    outside = {p for p in _files(tmp_path) - before if out not in p.parents}
    assert not outside
    return err


def _scenario(tmp_path: Path, name: str = "safe", sensor: str = "eo", modality: str = "eo") -> Path:
    path = tmp_path / "scenario.toml"
    path.write_text(
        f'name = {_toml(name)}\n[target]\npreset = "dji_mini_4_pro"\n'
        f"[sensors.{_toml(sensor)}]\nmodality = {_toml(modality)}\n",
        encoding="utf-8",
    )
    return path


# --- the base functions --------------------------------------------------------------------------


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_a_hostile_name_never_becomes_part_of_a_file_name(kind, tmp_path):
    with pytest.raises(ParameterError, match="sensors"):
        file_name_part(_hostile(kind, tmp_path), "sensors")


@pytest.mark.parametrize("name", ["default", "eo", "radar_2", "Site-A.v2", "_x", "a" * MAX_NAME_CHARS])
def test_ordinary_names_are_kept_as_written(name):
    assert file_name_part(name, "name") == name


@pytest.mark.parametrize("name", ["", ".hidden", "-flag", "a b", "a/b", "..", "a" * (MAX_NAME_CHARS + 1), 5, None])
def test_names_outside_the_pattern_are_refused(name):
    with pytest.raises(ParameterError):
        file_name_part(name, "name")


def test_a_path_leaving_the_output_folder_is_refused(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    assert inside(out, "a.png") == out / "a.png"
    assert inside(out, "sub", "a.png") == out / "sub" / "a.png"
    for parts in (("..", "a.png"), ("../../a.png",), (str(tmp_path / "x.png"),), ("a\0.png",), ("x" * 300,)):
        with pytest.raises(ParameterError, match="--out"):
            inside(out, *parts)


def test_a_linked_sub_folder_is_followed_and_refused(tmp_path):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (out / "images").symlink_to(elsewhere)
    with pytest.raises(ParameterError, match="inside the output folder"):
        inside(out, "images", "a.png")


def test_a_loop_of_links_is_refused_naming_the_option(tmp_path):
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    with pytest.raises(ParameterError, match="--out"):
        inside(tmp_path / "a", "x.png")


def test_a_linked_output_folder_is_the_users_choice(tmp_path):
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "link").symlink_to(real)
    assert inside(tmp_path / "link", "a.png").resolve() == real / "a.png"


def _special_files(tmp_path: Path) -> dict:
    """A character device (the major/minor of /dev/null), a FIFO and a folder, each named like an output."""
    nodes = {}
    null = os.stat("/dev/null").st_rdev
    nodes["chardev"] = tmp_path / "node.png"
    os.mknod(nodes["chardev"], stat.S_IFCHR | 0o666, null)
    nodes["fifo"] = tmp_path / "fifo.png"
    os.mkfifo(nodes["fifo"])
    nodes["folder"] = tmp_path / "folder.png"
    nodes["folder"].mkdir()
    return nodes


def _same_kind(path: Path, kind: str) -> bool:
    mode = os.lstat(path).st_mode
    return {"chardev": stat.S_ISCHR, "fifo": stat.S_ISFIFO, "folder": stat.S_ISDIR}[kind](mode)


needs_root = pytest.mark.skipif(os.geteuid() != 0, reason="mknod of a character device needs root")


@needs_root
def test_the_atomic_writer_never_replaces_a_special_file(tmp_path):
    for kind, node in _special_files(tmp_path).items():
        with pytest.raises(ParameterError, match="output file"):
            write_text_atomic(node, "x")
        with pytest.raises(ParameterError, match="never replaced"):
            with atomic_path(node):
                pytest.fail("the atomic writer started work on a special file")
        assert _same_kind(node, kind)
        with pytest.raises(ParameterError, match="--plot"):
            output_file(node, "--plot")
        with pytest.raises(ParameterError):
            refuse_special(node, "--plot")
    assert not [p for p in tmp_path.iterdir() if ".csuas-tmp-" in p.name]


def test_a_link_to_a_device_is_refused_and_a_regular_file_replaced(tmp_path):
    (tmp_path / "null.png").symlink_to("/dev/null")
    with pytest.raises(ParameterError, match="character device"):
        write_text_atomic(tmp_path / "null.png", "x")
    regular = tmp_path / "r.txt"
    regular.write_text("old")
    write_text_atomic(regular, "new")
    assert regular.read_text() == "new"


# --- single output files the user names -------------------------------------------------------------

#: Commands whose option names one output file; {} is the file (its suffix as the command requires).
SINGLE_FILE = {
    "rcs --plot": ["rcs", "black_hornet_3", "--frequency-ghz", "10", "--plot", "{}"],
    "pd --plot": ["pd", "default", "--plot", "{}"],
    "rcs-statistics --out": [
        "rcs-statistics", "--presets", "black_hornet_3", "--bands-ghz", "10", "--quality", "draft",
        "--max-aspects", "256", "--out", "{}",
    ],
    "drone --export": ["drone", "black_hornet_3", "--quality", "none", "--export", "{}"],
}  # fmt: skip
SUFFIX = {"rcs --plot": ".png", "pd --plot": ".png", "rcs-statistics --out": ".csv", "drone --export": ".ply"}


@needs_root
@pytest.mark.parametrize("command", sorted(SINGLE_FILE))
@pytest.mark.parametrize("kind", ["chardev", "fifo", "folder"])
def test_a_single_output_file_that_is_special_is_refused_before_work(command, kind, tmp_path, capsys):
    node = tmp_path / f"node{SUFFIX[command]}"
    if kind == "chardev":
        os.mknod(node, stat.S_IFCHR | 0o666, os.stat("/dev/null").st_rdev)
    elif kind == "fifo":
        os.mkfifo(node)
    else:
        node.mkdir()
    argv = [str(node) if a == "{}" else a for a in SINGLE_FILE[command]]
    option = command.split()[1].lstrip("-")
    _refused(argv, capsys, tmp_path, tmp_path / "none", f"{option} =", "never replaced")
    assert _same_kind(node, kind)


@pytest.mark.parametrize("command", sorted(SINGLE_FILE))
def test_a_single_output_file_with_a_nul_or_an_overlong_name_is_refused(command, tmp_path, capsys):
    for bad in (f"a\0b{SUFFIX[command]}", "x" * 300 + SUFFIX[command]):
        argv = [str(tmp_path / bad) if a == "{}" else a for a in SINGLE_FILE[command]]
        _refused(argv, capsys, tmp_path, tmp_path / "none", command.split()[1].lstrip("-") + " =")


# --- names that become file names --------------------------------------------------------------------


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_render_refuses_a_hostile_scenario_name_before_rendering(kind, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "out"
    scenario = _scenario(tmp_path, name=_hostile(kind, tmp_path))
    argv = ["render", "eo", scenario, "--range-m", "100", "--quality", "draft", "--out", out, "--quiet"]
    _refused(argv, capsys, tmp_path, out, "name =")
    assert not _files(out)


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_render_refuses_a_hostile_sensor_name_before_rendering(kind, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "out"
    scenario = _scenario(tmp_path, sensor=_hostile(kind, tmp_path))
    argv = ["render", "eo", scenario, "--range-m", "100", "--quality", "draft", "--out", out, "--quiet"]
    _refused(argv, capsys, tmp_path, out, "sensors =")
    assert not _files(out)


@pytest.mark.parametrize("kind", sorted(HOSTILE))
@pytest.mark.parametrize("where", ["name", "sensor"])
def test_sensitivity_refuses_a_hostile_name_before_plotting(kind, where, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "out"
    hostile = _hostile(kind, tmp_path)
    scenario = _scenario(tmp_path, **({"name": hostile} if where == "name" else {"sensor": hostile}))
    argv = ["sensitivity", "--scenario", scenario, "--vary", "target.d_crit_m=0.08:0.12", "--out", out]
    _refused(argv, capsys, tmp_path, out, "name =" if where == "name" else "sensors =")


def _site(tmp_path: Path, sensor: str) -> Path:
    scenario = _scenario(tmp_path, sensor=sensor)
    site = tmp_path / "site.toml"
    site.write_text(
        f"scenario = {_toml(str(scenario))}\naltitudes_agl_m = [30.0]\n"
        f"[sensors.{_toml(sensor)}]\nx = 505000.0\ny = 5005000.0\n",
        encoding="utf-8",
    )
    return site


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_coverage_refuses_a_hostile_sensor_name_before_tracing(kind, tmp_path, capsys):
    out = tmp_path / "a" / "b" / "out"
    site = _site(tmp_path, _hostile(kind, tmp_path))
    _refused(["coverage", site, "--out", out], capsys, tmp_path, out, "sensors =")
    assert not _files(out)


# --- output folders with links and special files inside ---------------------------------------------


def _dataset_spec(tmp_path: Path) -> Path:
    scenario = tmp_path / "small.toml"
    scenario.write_text(
        'name = "small"\n[target]\npreset = "dji_mini_4_pro"\n[sensors.eo]\nmodality = "eo"\nn_h = 64\nn_v = 48\n',
        encoding="utf-8",
    )
    spec = tmp_path / "spec.toml"
    spec.write_text(
        f'seed = 1\ncount = 1\nscenario = {_toml(str(scenario))}\ndrones = ["dji_mini_4_pro"]\nrange_m = [150.0]\n',
        encoding="utf-8",
    )
    return spec


def _sweep_spec(tmp_path: Path) -> Path:
    spec = tmp_path / "sweep.toml"
    spec.write_text('job = "range"\nscenario = "default"\n[axes]\n"target.d_crit_m" = [0.1, 0.2]\n', encoding="utf-8")
    return spec


#: Writing commands with an output folder: argv (``{out}`` is the folder) and a sub-folder they write into.
FOLDER_COMMANDS = {
    "dataset": (lambda t: ["dataset", _dataset_spec(t), "--out", "{out}"], "images"),
    "sweep": (lambda t: ["sweep", _sweep_spec(t), "--scheduler", "serial", "--out", "{out}"], "chunks"),
    "report": (lambda t: ["report", "--out", "{out}"], "figures"),
}


@pytest.mark.parametrize("command", sorted(FOLDER_COMMANDS))
def test_a_sub_folder_linked_elsewhere_is_refused_before_work(command, tmp_path, capsys):
    make_argv, sub = FOLDER_COMMANDS[command]
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (elsewhere / "keep.png").write_bytes(b"not csuas's")
    (out / sub).symlink_to(elsewhere)
    argv = [str(out) if a == "{out}" else a for a in make_argv(tmp_path)]
    _refused(argv, capsys, tmp_path, out, "inside the output folder")
    assert sorted(p.name for p in elsewhere.iterdir()) == ["keep.png"]


#: A file each folder command writes at its top level.
TOP_FILE = {"dataset": "annotations.json", "sweep": "sweep.json", "report": "report.json", "coverage": "coverage.json"}


@needs_root
@pytest.mark.parametrize("command", sorted(FOLDER_COMMANDS) + ["coverage", "sensitivity", "render"])
def test_a_device_node_in_the_output_folder_survives_and_is_refused_before_work(command, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    if command == "coverage":
        argv, name = ["coverage", _site(tmp_path, "eo"), "--out", out], TOP_FILE[command]
    elif command == "render":
        argv = ["render", "eo", _scenario(tmp_path), "--range-m", "100", "--quality", "draft", "--out", out, "--quiet"]
        name = "safe_eo_eo_r100m_az0_el0_draft.png"
    elif command == "sensitivity":
        scenario = _scenario(tmp_path)
        argv = ["sensitivity", "--scenario", scenario, "--vary", "target.d_crit_m=0.08:0.12", "--out", out]
        name = "tornado_safe_eo.png"
    else:
        make_argv, _ = FOLDER_COMMANDS[command]
        argv, name = [str(out) if a == "{out}" else a for a in make_argv(tmp_path)], TOP_FILE[command]
    node = out / name
    os.mknod(node, stat.S_IFCHR | 0o666, os.stat("/dev/null").st_rdev)
    _refused(argv, capsys, tmp_path, out, "never replaced")
    assert _same_kind(node, "chardev")


def test_sensitivity_into_a_linked_output_folder_writes_into_its_target_only(tmp_path, capsys):
    real = tmp_path / "real"
    real.mkdir()
    (tmp_path / "link").symlink_to(real)
    scenario = _scenario(tmp_path)
    argv = ["sensitivity", "--scenario", scenario, "--vary", "target.d_crit_m=0.08:0.12", "--out", tmp_path / "link"]
    code, err = _run(argv, capsys)
    assert code == 0, err
    assert sorted(p.name for p in real.iterdir()) == ["tornado_safe_eo.png"]


def test_a_link_in_the_output_folder_is_replaced_and_its_target_elsewhere_never_written(tmp_path, capsys):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    victim = elsewhere / "victim.png"
    victim.write_bytes(b"not csuas's")
    link = out / "safe_eo_eo_r100m_az0_el0_draft.png"
    link.symlink_to(victim)
    argv = ["render", "eo", _scenario(tmp_path), "--range-m", "100", "--quality", "draft", "--out", out, "--quiet"]
    code, err = _run(argv, capsys)
    assert code == 0, err
    assert victim.read_bytes() == b"not csuas's"
    assert not link.is_symlink() and link.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_coverage_checks_exactly_the_files_it_writes(tmp_path, capsys):
    """The layer names checked before the work (csuas.commands.coverage._layer_files) are the files written."""
    from csuas.commands.coverage import LOCK_NAME, _layer_files

    site = tmp_path / "site.toml"
    site.write_text(
        "altitudes_agl_m = [30.0]\nfusion_k = 1\n[sensors.eo]\nx = 505000.0\ny = 5005000.0\n", encoding="utf-8"
    )
    out = tmp_path / "out"
    code, err = _run(["coverage", site, "--out", out], capsys)
    assert code == 0, err
    written = sorted(p.name for p in out.iterdir() if p.name != LOCK_NAME)
    assert written == sorted(_layer_files(["eo"], [30.0], [], 1))


@needs_root
def test_a_device_node_named_like_a_coverage_layer_survives_and_is_refused_before_work(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    node = out / "eo_detected_30m.geojson"
    os.mknod(node, stat.S_IFCHR | 0o666, os.stat("/dev/null").st_rdev)
    _refused(["coverage", _site(tmp_path, "eo"), "--out", out], capsys, tmp_path, out, "never replaced")
    assert _same_kind(node, "chardev")
    assert sorted(p.name for p in out.iterdir()) == ["eo_detected_30m.geojson"]


def test_a_site_sensor_named_fused_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    _refused(["coverage", _site(tmp_path, "fused"), "--out", out], capsys, tmp_path, out, "fused layers")


#: Every command with an output folder, its argv with {} for the folder (cheap settings: refused before work).
OUT_FOLDER_COMMANDS = {
    "render": ["render", "eo", "default", "--range-m", "100", "--quality", "draft", "--out", "{}"],
    "sensitivity": ["sensitivity", "--analysis", "eo", "--out", "{}"],
    "dataset": ["dataset", "example", "--out", "{}"],
    "sweep": ["sweep", "range_rain", "--scheduler", "serial", "--out", "{}"],
    "coverage": ["coverage", "demo", "--out", "{}"],
    "report": ["report", "--out", "{}"],
}


@pytest.mark.parametrize("command", sorted(OUT_FOLDER_COMMANDS))
@pytest.mark.parametrize("bad", ["nul", "long"])
def test_an_output_folder_with_a_nul_or_an_overlong_name_is_refused_before_work(command, bad, tmp_path, capsys):
    folder = str(tmp_path / ("a\0b" if bad == "nul" else "x" * 300))
    argv = [folder if a == "{}" else a for a in OUT_FOLDER_COMMANDS[command]]
    _refused(argv, capsys, tmp_path, tmp_path / "none", "out =")
    assert not list(tmp_path.iterdir())
