# Where a case's pipeline finds the programs and writes its runs; included by
# pipeline.mk and by the cases with a Makefile of their own (column-seismic), after they
# set CASE_DIR.
ROOT    := $(abspath $(CASE_DIR)/../..)
BUILD   ?= $(ROOT)/build
BIN     ?= $(BUILD)/bin
PYTHON  ?= /usr/bin/python3
OUT     ?= $(CASE_DIR)/out
# A relative OUT from the command line or the environment is taken from the caller's
# directory: the shell's PWD, which `make -C` leaves as it was (CURDIR is the case's).
# Sub-makes are given the absolute OUT, since their shells' PWD is the case folder.
ifneq ($(filter command line environment,$(origin OUT)),)
  override OUT := $(abspath $(if $(filter /%,$(OUT)),$(OUT),$(or $(PWD),$(CURDIR))/$(OUT)))
endif
TOOLS   := $(ROOT)/tools
