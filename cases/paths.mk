# Where a case's pipeline finds the programs and writes its runs; included by
# pipeline.mk and by the cases with a Makefile of their own (column-seismic), after they
# set CASE_DIR.
ROOT    := $(abspath $(CASE_DIR)/../..)
BUILD   ?= $(ROOT)/build
BIN     ?= $(BUILD)/bin
PYTHON  ?= /usr/bin/python3
OUT_DEFAULT := $(CASE_DIR)/out
OUT     ?= $(OUT_DEFAULT)
include $(CASE_DIR)/../out.mk
TOOLS   := $(ROOT)/tools
# The mark of a folder the pipeline writes to: `make clean` removes only in such a folder
# (tools/clean-outputs.sh). Every first rule that writes to OUT has it as an order-only
# prerequisite.
OUT_STAMP := $(OUT)/.slide-outputs
$(OUT_STAMP):
	@mkdir -p $(OUT) && touch $@
CLEAN := $(TOOLS)/clean-outputs.sh
