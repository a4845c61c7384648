# Where a case's pipeline finds the programs and writes its runs; included by
# pipeline.mk and by the cases with a Makefile of their own (column-seismic), after they
# set CASE_DIR.
#
# The pipeline's own files (this one, pipeline.mk, out.mk) sit together: in the source
# tree's cases/, or installed in <prefix>/share/slide/cases/ (`cmake --install`), where
# the install adds installed.mk, which names the installed programs and tools. A case
# folder may be anywhere: it includes pipeline.mk by its path (cases/template/Makefile).
SLIDE_MAKE_DIR := $(abspath $(dir $(lastword $(MAKEFILE_LIST))))
-include $(SLIDE_MAKE_DIR)/installed.mk
ifdef SLIDE_INSTALLED_BIN
  ROOT  := $(SLIDE_INSTALLED_SHARE)
  BIN   ?= $(SLIDE_INSTALLED_BIN)
  BUILD ?= $(BIN)/..
  TOOLS := $(SLIDE_INSTALLED_SHARE)/tools
else
  ROOT  := $(abspath $(SLIDE_MAKE_DIR)/..)
  BUILD ?= $(ROOT)/build
  BIN   ?= $(BUILD)/bin
  TOOLS := $(ROOT)/tools
endif
PYTHON  ?= /usr/bin/python3
OUT_DEFAULT := $(CASE_DIR)/out
OUT     ?= $(OUT_DEFAULT)
include $(SLIDE_MAKE_DIR)/out.mk
# The mark of a folder the pipeline writes to: `make clean` removes only in such a folder
# (tools/clean-outputs.sh). Every first rule that writes to OUT has it as an order-only
# prerequisite.
OUT_STAMP := $(OUT)/.slide-outputs
$(OUT_STAMP):
	@mkdir -p $(OUT) && touch $@
CLEAN := $(TOOLS)/clean-outputs.sh
