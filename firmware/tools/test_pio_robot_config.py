"""Tests firmware/tools/pio_robot_config.py, the PlatformIO extra script, without PlatformIO:
it runs under a stand-in for the SCons environment, as `pio run` would run it."""
import json
import pathlib
import runpy

import pytest

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent.parent
SCRIPT = HERE / "pio_robot_config.py"


class FakeEnv:
    """The few SCons/PlatformIO environment calls the script makes."""

    def __init__(self, build_dir, options):
        self.vars = {"$PROJECT_DIR": str(ROOT), "$BUILD_DIR": str(build_dir)}
        self.options = options
        self.cpppath = []
        self.exit_code = None

    def subst(self, text):
        return self.vars[text]

    def GetProjectOption(self, name, default=None):  # noqa: N802 - PlatformIO's name
        return self.options.get(name, default)

    def Append(self, CPPPATH=()):  # noqa: N802,N803 - SCons's names
        self.cpppath.extend(CPPPATH)

    def Exit(self, code):  # noqa: N802 - SCons's name
        self.exit_code = code


def run_script(env):
    runpy.run_path(str(SCRIPT), init_globals={"Import": lambda name: None, "env": env})


def test_writes_the_header_and_adds_its_directory(tmp_path):
    env = FakeEnv(tmp_path, {"custom_robot": "robots/mk2plus.json"})
    run_script(env)
    assert env.exit_code is None
    assert env.cpppath == [str(tmp_path / "articula_generated")]
    header = (tmp_path / "articula_generated" / "robot_config.h").read_text()
    assert '#define ARTICULA_ROBOT_NAME "MK2 Plus"' in header


def test_another_robot_by_absolute_path(tmp_path):
    robot = json.loads((ROOT / "robots" / "mk2plus.json").read_text())
    robot["name"] = "Other arm"
    path = tmp_path / "other.json"
    path.write_text(json.dumps(robot))
    env = FakeEnv(tmp_path / "build", {"custom_robot": str(path)})
    run_script(env)
    header = (tmp_path / "build" / "articula_generated" / "robot_config.h").read_text()
    assert '#define ARTICULA_ROBOT_NAME "Other arm"' in header


def test_a_missing_robot_file_stops_the_build(tmp_path, capsys):
    env = FakeEnv(tmp_path, {"custom_robot": "robots/no_such_robot.json"})
    run_script(env)
    assert env.exit_code == 1
    assert env.cpppath == []
    assert "custom_robot" in capsys.readouterr().out


@pytest.mark.parametrize("env_name", ["nano", "nano_new", "native"])
def test_every_environment_runs_the_script_and_names_a_robot(env_name):
    # PlatformIO's own parser, as `pio run` reads the file.
    config_module = pytest.importorskip("platformio.project.config")
    config = config_module.ProjectConfig(str(ROOT / "platformio.ini"))
    section = f"env:{env_name}"
    assert "pre:firmware/tools/pio_robot_config.py" in config.get(section, "extra_scripts")
    assert (ROOT / config.get(section, "custom_robot")).is_file()


def test_platformio_knows_every_option():
    # `pio project config` accepts a misspelt option silently (and PlatformIO then ignores
    # it); check each against PlatformIO's own table. custom_* options are ours by design.
    config_module = pytest.importorskip("platformio.project.config")
    options_module = pytest.importorskip("platformio.project.options")
    config = config_module.ProjectConfig(str(ROOT / "platformio.ini"))
    unknown = []
    for section in config.sections():
        scope = "platformio" if section == "platformio" else "env"
        for option in config.options(section):
            if not option.startswith("custom_") and f"{scope}.{option}" not in options_module.ProjectOptions:
                unknown.append(f"[{section}] {option}")
    assert unknown == []
