"""PlatformIO's extra script for the AVR environments (platformio.ini: extra_scripts = pre:...):
the firmware's flags from firmware/flags.txt, the file the CMake build reads too, so both
builds compile and link the same code the same way. firmware/tools/check_pio_flags.py (the
test firmware.avr_flags_agree) runs this script on a stand-in environment and compares.

PlatformIO's AVR builder brings the part and its clock from the board, and defaults of its
own; those the firmware's flags say otherwise about are taken out (-fpermissive: a C++ error
stays an error, as in the CMake build).
"""
import shlex
from pathlib import Path

Import("env")  # noqa: F821 (SCons gives it)


def firmware_flags(project_dir: str) -> dict[str, list[str]]:
    """firmware/flags.txt as {name: [flag, ...]}."""
    out: dict[str, list[str]] = {}
    for line in (Path(project_dir) / "firmware" / "flags.txt").read_text().splitlines():
        name, sep, flags = line.partition(":")
        if sep and name.isalpha() and name.islower() and not line.startswith("#"):
            out[name] = shlex.split(flags)
    return out


flags = firmware_flags(env.subst("$PROJECT_DIR"))  # noqa: F821
for unwanted in ("-fpermissive",):
    for key in ("CCFLAGS", "CXXFLAGS"):
        if unwanted in env.get(key, []):  # noqa: F821
            env[key].remove(unwanted)  # noqa: F821
env.Append(  # noqa: F821
    CXXFLAGS=flags["language"],
    CCFLAGS=flags["warnings"] + flags["size"],
    LINKFLAGS=flags["size"] + flags["link"],
)
