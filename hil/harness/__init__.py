"""The hardware-in-the-loop harness: test plans run on the arm or the virtual Nano, compared
command by command with `articula predict` (hil/README.md, "The harness")."""
