# Where runs go, for the case pipelines (paths.mk) and cases/Makefile: OUT from the command
# line, absolute or taken from the caller's directory. Included after OUT's default is set
# (the folder's own out/).
#
# OUT= given empty is refused: it used to become the caller's directory, which `make clean`
# then removed. An OUT exported in the environment (by something else, say) is ignored,
# with a note, unless OUT_FROM_ENVIRONMENT=yes: a pipeline writes, and cleans, only where
# it was told to.
ifeq ($(origin OUT),environment)
  ifeq ($(OUT_FROM_ENVIRONMENT),yes)
    override OUT := $(OUT)
  else
    $(info note: OUT=$(OUT) of the environment is ignored (give OUT=... to make, or OUT_FROM_ENVIRONMENT=yes))
    override OUT := $(OUT_DEFAULT)
    unexport OUT
  endif
endif
ifeq ($(origin OUT),command line)
  ifeq ($(strip $(OUT)),)
    $(error OUT= is empty: name the folder the runs go to, or leave OUT out for $(OUT_DEFAULT))
  endif
endif
# A relative OUT is taken from the caller's directory: the shell's PWD, which `make -C`
# leaves as it was (CURDIR is the case's). Sub-makes are given the absolute OUT.
ifneq ($(strip $(OUT)),)
  override OUT := $(abspath $(if $(filter /%,$(OUT)),$(OUT),$(or $(PWD),$(CURDIR))/$(OUT)))
endif
