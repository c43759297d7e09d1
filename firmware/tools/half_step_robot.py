#!/usr/bin/env python3
"""A robot file's arm driven in half steps: every motor's microsteps set to 2.

    half_step_robot.py ROBOT.json OUTPUT.json

Used by the AVR build for articula-nano-halfstep.elf, a test build of the firmware that the
virtual Nano's throughput test runs (hil/tests/test_vnano.py): in half steps the MK2's
motors have twice the steps over the same ranges, so all three can step together at the
top rate long enough to measure. Standard library only.
"""
import json
import sys


def main(argv):
    if len(argv) != 3:
        sys.stderr.write(__doc__)
        return 2
    with open(argv[1], encoding="utf-8") as f:
        robot = json.load(f)
    for motor in robot["motors"]:
        motor["microsteps"] = 2
    robot["name"] = (robot["name"] + " half-step")[:24]  # the protocol's longest name
    robot.pop("$schema", None)
    with open(argv[2], "w", encoding="utf-8") as f:
        json.dump(robot, f, indent=1)
        f.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
