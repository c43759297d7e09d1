"""Do PlatformIO's AVR environments compile and link the firmware as the CMake build does?

Reads, for each CMake firmware build (articula-nano, -cnc, -servo), the flags its ninja file
gives a firmware source's compile and the image's link; runs PlatformIO's extra script
(firmware/tools/pio_flags.py) on a stand-in for each AVR environment of platformio.ini (its
`extends`, `build_flags` and `extra_scripts` resolved); and fails, naming the environment and
the flag, where one build has a flag the other has not. Not compared: what each build's board
or toolchain gives on its own (the part, the clock: -mmcu, F_CPU), CMake's build type's
-DNDEBUG (the firmware has no assert), and the simavr section's link options (CMake only).

    python firmware/tools/check_pio_flags.py build/avr/build.ninja
"""
from __future__ import annotations

import configparser
import re
import shlex
import sys
from pathlib import Path

SOURCE = Path(__file__).resolve().parents[2]
BUILD_OF = {None: "articula-nano", "ARTICULA_CNC_SHIELD": "articula-cnc", "ARTICULA_SERVO_ARM": "articula-servo"}


def cmake_flags(ninja: Path, target: str) -> tuple[set[str], set[str], set[str]]:
    """(compile flags, link flags, defines) of a CMake firmware build, from its ninja file."""
    text = ninja.read_text()
    comp = re.search(rf"^build firmware/CMakeFiles/{target}\.dir/src/stepper\.cpp\.obj:.*\n((?:  .*\n)+)", text, re.M)
    link = re.search(rf"^build firmware/{target}\.elf:.*\n((?:  .*\n)+)", text, re.M)
    if not comp or not link:
        raise SystemExit(f"{ninja}: no compile of stepper.cpp or link of {target}.elf (run `make build` first)")

    def var(block: str, name: str) -> list[str]:
        m = re.search(rf"^  {name} = (.*)$", block, re.M)
        return shlex.split(m.group(1)) if m else []

    compile_flags = set(var(comp.group(1), "FLAGS"))
    link_flags = {f for f in var(link.group(1), "LINK_FLAGS") if "mmcu=0x" not in f and "_mmcu" not in f}
    defines = {d[2:] for d in var(comp.group(1), "DEFINES")}
    return compile_flags, link_flags, defines


def pio_envs(ini: Path) -> dict[str, dict[str, str]]:
    """Each [env:NAME] of platformio.ini with its `extends` chain and ${env.x} resolved."""
    cp = configparser.ConfigParser(interpolation=None)
    cp.read(ini)
    base = dict(cp["env"]) if cp.has_section("env") else {}

    def resolved(section: str, seen: tuple[str, ...] = ()) -> dict[str, str]:
        own = dict(cp[section])
        out = dict(base)
        if "extends" in own:
            parent = own["extends"].strip()
            if parent in seen:
                raise SystemExit(f"{ini}: [{section}] extends itself through {parent}")
            out.update(resolved(parent, seen + (section,)))
        out.update(own)
        return {k: re.sub(r"\$\{env\.(\w+)\}", lambda m: base.get(m.group(1), ""), v) for k, v in out.items()}

    return {s[4:]: resolved(s) for s in cp.sections() if s.startswith("env:")}


class StandIn(dict):
    """What pio_flags.py uses of a PlatformIO SCons environment."""

    def __init__(self, project_dir: Path):
        super().__init__(CCFLAGS=["-Os", "-Wall", "-ffunction-sections", "-fdata-sections", "-flto"],
                         CXXFLAGS=["-fno-exceptions", "-fno-threadsafe-statics", "-fpermissive", "-std=gnu++11"],
                         LINKFLAGS=["-Os", "-Wl,--gc-sections", "-flto", "-fuse-linker-plugin"])
        self.project_dir = project_dir

    def subst(self, s: str) -> str:
        return s.replace("$PROJECT_DIR", str(self.project_dir))

    def Append(self, **kw: list[str]) -> None:  # noqa: N802 (SCons's name)
        for k, v in kw.items():
            self.setdefault(k, []).extend(v)


def run_script(script: Path, project_dir: Path) -> StandIn:
    env = StandIn(project_dir)
    code = compile(script.read_text(), str(script), "exec")
    exec(code, {"Import": lambda *_: None, "env": env, "__name__": "SCons"})
    return env


def main(argv: list[str]) -> int:
    ninja = Path(argv[1]) if len(argv) > 1 else SOURCE / "build" / "avr" / "build.ninja"
    ini = Path(argv[2]) if len(argv) > 2 else SOURCE / "platformio.ini"
    problems: list[str] = []
    checked = 0
    for name, env in pio_envs(ini).items():
        if env.get("platform") != "atmelavr":
            continue
        scripts = [s.strip() for s in env.get("extra_scripts", "").replace(",", "\n").split("\n") if s.strip()]
        pio = StandIn(ini.parent)
        for s in scripts:
            path = ini.parent / s.split(":", 1)[-1]
            if not path.exists():
                problems.append(f"[env:{name}]: its extra script {s} is missing")
                continue
            pio = run_script(path, ini.parent)
        defines = {d[2:].strip() for d in re.findall(r"-D\s*\w+", env.get("build_flags", ""))}
        build = BUILD_OF.get(next(iter(defines & set(BUILD_OF)), None))
        c_compile, c_link, c_defines = cmake_flags(ninja, build)
        ignore = {"-DNDEBUG"} | {f for f in c_compile | c_link if f.startswith(("-mmcu=", "-DF_CPU="))}
        p_compile = set(pio["CCFLAGS"]) | set(pio["CXXFLAGS"])
        p_link = set(pio["LINKFLAGS"])
        for what, cm, pi in (("compile", c_compile, p_compile), ("link", c_link, p_link)):
            for f in sorted(cm - pi - ignore):
                problems.append(f"[env:{name}] ({build}): CMake's {what} has {f}, PlatformIO's has not")
            for f in sorted(pi - cm - ignore):
                problems.append(f"[env:{name}] ({build}): PlatformIO's {what} has {f}, CMake's has not")
        if defines != c_defines:
            problems.append(f"[env:{name}] ({build}): defines {sorted(defines)} against CMake's {sorted(c_defines)}")
        if "framework" in env:
            problems.append(f"[env:{name}]: framework = {env['framework']} (the CMake build links no framework)")
        checked += 1
        print(f"[env:{name}] as {build}: {len(p_compile)} compile and {len(p_link)} link flags")
    for p in problems:
        print(p, file=sys.stderr)
    if checked == 0:
        print(f"{ini}: no AVR environment", file=sys.stderr)
        return 1
    print(f"{checked} environments: " + ("the same flags as the CMake build" if not problems else f"{len(problems)} differences"))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
