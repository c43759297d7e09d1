"""PlatformIO extra script (pre:): robot_config.h for the firmware, from a robot file.

platformio.ini names the robot file with `custom_robot` (a path relative to the project);
this script runs robot_config.py on it into <build dir>/articula_generated/robot_config.h
and puts that directory on the include path, as firmware/avr.cmake does for the CMake
build. It runs at the start of every `pio run` / `pio test`; robot_config.py rewrites the
header only when its text changes, so an unchanged robot rebuilds nothing.
"""
import importlib.util
import os

Import("env")  # noqa: F821 - provided by SCons when PlatformIO runs this script


def robot_config_header(project_dir, robot, build_dir):
    """Writes robot_config.h for `robot` under build_dir; returns the directory to include,
    or raises RuntimeError with the reason."""
    tool = os.path.join(project_dir, "firmware", "tools", "robot_config.py")
    spec = importlib.util.spec_from_file_location("articula_robot_config", tool)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    robot_path = robot if os.path.isabs(robot) else os.path.join(project_dir, robot)
    out_dir = os.path.join(build_dir, "articula_generated")
    if module.main(["robot_config.py", robot_path, os.path.join(out_dir, "robot_config.h")]) != 0:
        raise RuntimeError(f"robot_config.py failed for {robot_path} (custom_robot in platformio.ini)")
    return out_dir


def main(env):
    project_dir = env.subst("$PROJECT_DIR")
    robot = env.GetProjectOption("custom_robot", "robots/mk2plus.json")
    try:
        include_dir = robot_config_header(project_dir, robot, env.subst("$BUILD_DIR"))
    except RuntimeError as e:
        print(f"Error: {e}")
        env.Exit(1)
        return
    print(f"Articula: robot_config.h from {robot}")
    env.Append(CPPPATH=[include_dir])


main(env)  # noqa: F821
