# Articula - the commands a user types. Each target installs what it needs first
# (scripts/bootstrap is idempotent and quick when everything is there).
#
#   make          build everything (host tools and AVR targets)
#   make test     install, build, run every test, print a summary
#   make demo     install, build, run the main job on the MK2 arm
#   make clean    remove the build tree

BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
ARTICULA = $(BUILD)/host/cli/articula

.PHONY: all build bootstrap test demo clean format

all: build

bootstrap:
	@bash scripts/bootstrap

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja

build: bootstrap $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

test: build
	@echo "== tests (ctest) =="
	ctest --test-dir $(BUILD) -j $(JOBS) --output-on-failure
	@bash scripts/test-summary $(BUILD)

demo: build
	@echo "== the MK2 Plus arm: its DH table =="
	@$(ARTICULA) info mk2plus
	@echo
	@echo "== the tool position for a pose (base 30, shoulder 60, elbow -80 deg) =="
	@$(ARTICULA) fk mk2plus --q 30,60,-80
	@echo
	@echo "== what whole motor steps make of a few L moves =="
	@$(ARTICULA) quantize mk2plus "L 0 10" "L 1 -12.5" "L 2 7.3" "L 0 -10" "L 0 0.1" "S 1"

format:
	clang-format -i shared/articula/*.h shared/tests/*.cpp shared/avr_check/*.cpp host/*/*.cpp host/*/*.h

clean:
	rm -rf $(BUILD)
