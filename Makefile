# softmc: the two entry points of the README. Both install what is missing, then build.
BUILD ?= build
JOBS  ?= $(shell nproc)
PLOT  ?= rounded_rectangle.svg

.PHONY: run test build bootstrap clean bench

bootstrap:
	@bash scripts/bootstrap.sh

$(BUILD)/build.ninja: | bootstrap
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null

build: bootstrap $(BUILD)/build.ninja
	@cmake --build $(BUILD) -j $(JOBS)

# The main job: the thesis's rounded rectangle on the built-in simulated cutting table.
run: build
	@$(BUILD)/apps/softmc/softmc run examples/thesis/rounded_rectangle.ngc --plot $(PLOT)
	@echo "plot written to $(PLOT): open it in a browser or image viewer"

test: build
	@cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

bench: build
	@$(BUILD)/bench/softmc_bench

clean:
	rm -rf $(BUILD)
