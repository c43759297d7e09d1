# Articula - the commands a user types. Each target installs what it needs first
# (scripts/bootstrap is idempotent and quick when everything is there).
#
#   make          build everything (host tools, AVR targets, the Nano firmware and its sizes)
#   make test     install, build, run every test, print a summary
#   make test-loaded  the same tests with two busy processes beside them (none may need a quiet machine)
#   make test-cpu [CORES=0.5]  the same tests, with the CPU seconds each suite took (scripts/cpu-by-suite);
#                 CORES holds them to that many cores (a cgroup, as root): a slow machine
#   make demo     install, build, run the thesis experiments on the virtual Nano, report
#   make studio   install, build, serve Articula Studio on 127.0.0.1 and open it in the browser
#   make web      build only the studio's static site (studio/web/dist), for any web server
#   make firmware build only the Nano firmware (HEX and ELF)
#   make flash PORT=/dev/ttyUSB0 [BOOTLOADER=new] [DRIVE=cnc|servo]
#                 flash the HEX into a Nano through its USB bootloader (DRIVE=cnc: the build
#                 for a CNC shield's STEP/DIR drivers; DRIVE=servo: for hobby-servo arms)
#   make clean    remove the build tree

BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
ARTICULA = $(BUILD)/host/cli/articula

# The Nano firmware, built by the AVR external project of the CMake build.
FIRMWARE_DIR = $(BUILD)/avr/firmware
# The build for the arm's drivers: nano (L298N, ULN2003), cnc (STEP/DIR in a CNC shield) or servo.
DRIVE ?= nano
HEX = $(FIRMWARE_DIR)/articula-$(DRIVE).hex
# Where `make demo` writes its hardware-in-the-loop report (replaced on each run).
DEMO_REPORT ?= reports/demo
# Nanos with the old bootloader (ATmegaBOOT, most clones) take 57,600 baud; those with the
# new one (Optiboot) 115,200. BAUD overrides both.
BOOTLOADER ?= old
BAUD_old = 57600
BAUD_new = 115200
BAUD ?= $(BAUD_$(BOOTLOADER))

.PHONY: all build bootstrap test test-loaded test-cpu demo studio web firmware flash clean format

all: build

bootstrap:
	@bash scripts/bootstrap

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja

build: bootstrap $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)
	@ln -sf "$(abspath $(ARTICULA))" .venv/bin/articula
	@printf '#!/bin/sh\nexec "%s" -m articula.studio "$$@"\n' "$(abspath .venv/bin/python)" > .venv/bin/articula-studio
	@chmod +x .venv/bin/articula-studio
	@echo "firmware: $(HEX)"
	@echo "commands: .venv/bin/articula and .venv/bin/articula-studio (or: source .venv/bin/activate)"

web: bootstrap $(BUILD)/build.ninja
	cmake --build $(BUILD) --target studio_web -j $(JOBS)
	@echo "studio: the static site is in studio/web/dist: serve that folder from any web server (see README)"

firmware: bootstrap $(BUILD)/build.ninja
	cmake --build $(BUILD) --target avr-configure
	cmake --build $(BUILD)/avr --target articula-nano-hex articula-cnc-hex articula-servo-hex -j $(JOBS)
	@echo "firmware: $(HEX) (flash it with: make flash PORT=/dev/ttyUSB0, see firmware/README.md)"

flash: firmware
	@[ -n "$(PORT)" ] || { echo "make flash: name the Nano's serial port, e.g. make flash PORT=/dev/ttyUSB0"; exit 2; }
	@[ -f "$(HEX)" ] || { echo "make flash: no $(HEX) (DRIVE is nano, cnc or servo)"; exit 2; }
	@[ -n "$(BAUD)" ] || { echo "make flash: BOOTLOADER is old or new (or give BAUD=...)"; exit 2; }
	avrdude -p atmega328p -c arduino -P $(PORT) -b $(BAUD) -D -U flash:w:$(HEX):i

test: build
	@echo "== tests (ctest) =="
	@rc=0; ctest --test-dir $(BUILD) -j $(JOBS) --output-on-failure --output-junit ctest-junit.xml || rc=$$?; \
	bash scripts/test-summary $(BUILD)/ctest-junit.xml; exit $$rc

test-loaded: build
	@bash scripts/test-loaded $(BUILD) $(JOBS)

test-cpu: build
	@echo "== tests (ctest), their CPU seconds by suite$(if $(CORES), held to $(CORES) cores) =="
	python3 scripts/cpu-by-suite $(if $(CORES),--cgroup-cpu $(CORES)) --json $(BUILD)/test-cpu.json -- \
	  ctest --test-dir $(BUILD) -j $(JOBS) --output-on-failure --output-junit ctest-cpu-junit.xml
	@bash scripts/test-summary $(BUILD)/ctest-cpu-junit.xml

demo: build
	@echo "== the MK2 Plus arm: its DH table =="
	@$(ARTICULA) info mk2plus
	@echo
	@echo "== the thesis's experiments on the virtual Nano: the real firmware, step by step against the prediction =="
	@rm -rf $(DEMO_REPORT)
	@.venv/bin/python -m hil.harness run hil/plans/thesis-single-joint.arm hil/plans/thesis-repeatability.arm \
	  hil/plans/tool-points.arm --out $(DEMO_REPORT) \
	  --vnano $(BUILD)/virtual-nano/articula-vnano --elf $(FIRMWARE_DIR)/articula-nano.elf
	@echo "open $(DEMO_REPORT)/report.html in a browser, or read $(DEMO_REPORT)/report.md"

# ROBOT=panda, PORT=8080, STUDIO_ARGS=--no-browser: passed to articula-studio, which serves
# the static site on 127.0.0.1 and connects the arm.
# The build's messages go to stderr: the first line on stdout is the studio's address.
studio:
	@$(MAKE) --no-print-directory build >&2
	@.venv/bin/articula-studio $(ROBOT) $(if $(PORT),--port $(PORT)) $(STUDIO_ARGS)

format:
	clang-format -i shared/articula/*.h shared/tests/*.cpp shared/avr_check/*.cpp host/*/*.cpp host/*/*.h \
	  firmware/src/*.cpp firmware/src/*.h

clean:
	rm -rf $(BUILD)
