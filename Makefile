# dermis — one plain Makefile.
#   make [config=release|debug|sanitize]   build every library, tool, test and benchmark
#   make test     install missing packages, build, run every test binary
#   make bench    run the accuracy-versus-time benchmarks, tables in bench/results/
#   make demo     install, build, bake and render the bundled head
#   make reference  the head's ground truth (dermis-reference) in tiles through GNU parallel
#   make deps     install the Debian packages that are missing (scripts/deps.sh)
#   make fuzz     build the libFuzzer targets (clang); make test runs each for FUZZ_SECONDS
#   make install / uninstall   [PREFIX=/usr/local] [DESTDIR=]: tools, man pages, headers,
#                 static libraries, pkg-config files, bash completions (docs/install.md)
#   make clean
# Outputs go under build/$(config)/. New files are picked up by wildcard: a C file in
# lib/<side>/ joins that side's library, tools/NAME.c becomes build/$(config)/bin/NAME,
# tests/<group>/NAME.c becomes a Criterion binary, bench/NAME.c a benchmark.

config  ?= release
SHARED  ?= ../shared
ASSETS  ?= $(SHARED)/assets
BUILD   := build/$(config)

CC      ?= gcc
CXX     ?= g++
PKG     ?= pkg-config
NPROC   ?= $(shell nproc 2>/dev/null || echo 2)

ifeq ($(config),release)
  OPT := -O2 -g
else ifeq ($(config),debug)
  OPT := -O0 -g3
else ifeq ($(config),sanitize)
  OPT := -O1 -g -fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined
else
  $(error config must be release, debug or sanitize, not '$(config)')
endif

WARN     := -Wall -Wextra -Wpedantic
CPPFLAGS := -Ilib -I$(BUILD)/gen -D_POSIX_C_SOURCE=200809L -MMD -MP
CFLAGS   := -std=c11 $(OPT) $(WARN) -pthread
CXXFLAGS := -std=c++17 $(OPT) $(WARN) -pthread
# --as-needed: a tool loads only the libraries it calls (OpenImageIO alone costs ~0.3 s).
LDFLAGS  := $(OPT) -pthread -Wl,--as-needed

# Dependencies, by side. The runtime side (lib/core, lib/pack, lib/render, lib/host) needs libc,
# cJSON, xxHash and zlib only (and the caller's GL); the offline side (lib/image, lib/mesh,
# lib/bake, lib/reference, lib/packer) adds OpenEXR, OpenImageIO, OpenMesh, tinygltf, Embree.
# docs/architecture.md draws the folders; scripts/check-layers.sh checks who includes whom.
CORE_CFLAGS   := $(shell $(PKG) --cflags libcjson libxxhash 2>/dev/null)
CORE_LIBS     := $(shell $(PKG) --libs libcjson libxxhash zlib 2>/dev/null) -lm
BAKE_CFLAGS   := $(shell $(PKG) --cflags OpenEXR OpenImageIO openmesh tinygltf 2>/dev/null)
BAKE_LIBS     := $(shell $(PKG) --libs OpenImageIO openmesh tinygltf 2>/dev/null) -lOpenEXRCore-3_1 -lembree3 -lz
OSMESA_LIBS   := $(shell $(PKG) --libs osmesa 2>/dev/null)
GLFW_LIBS     := $(shell $(PKG) --libs glfw3 2>/dev/null) -lGL
TEST_CFLAGS   := $(shell $(PKG) --cflags criterion 2>/dev/null)
TEST_LIBS     := $(shell $(PKG) --libs criterion 2>/dev/null)

# One archive per side: libdermis_core (core, pack), libdermis_render (render and its
# subfolders), libdermis_host_osmesa, libdermis_bake (the offline folders).
CORE_DIRS    := core pack
OFFLINE_DIRS := image mesh bake reference packer
CORE_SRC   := $(sort $(foreach d,$(CORE_DIRS),$(wildcard lib/$(d)/*.c)))
BAKE_SRC   := $(sort $(foreach d,$(OFFLINE_DIRS),$(wildcard lib/$(d)/*.c lib/$(d)/*.cpp)))
RENDER_SRC := $(sort $(wildcard lib/render/*.c lib/render/*/*.c))
HOST_SRC   := $(sort $(wildcard lib/host/*.c))
# Shaders are embedded at build time: scripts/embed-shaders.sh turns shaders/*.glsl into
# one generated C file (byte arrays + a name table) that joins the render library.
SHADERS    := $(sort $(wildcard shaders/*.glsl))
SHADER_GEN := $(BUILD)/gen/dm_shaders_gen.c

obj = $(patsubst %,$(BUILD)/obj/%.o,$(1))

CORE_LIB   := $(BUILD)/lib/libdermis_core.a
BAKE_LIB   := $(BUILD)/lib/libdermis_bake.a
RENDER_LIB := $(BUILD)/lib/libdermis_render.a
HOST_LIB   := $(BUILD)/lib/libdermis_host_osmesa.a

# Runtime tools never link the offline side's third-party libraries (DESIGN.md): they are
# listed by name.
RUNTIME_TOOLS := dermis-render dermis-view
# Offline tools that also drive the renderer headless (the ground truth reads the
# renderer's own irradiance): both sides, like the render tests.
BOTH_TOOLS    := dermis-reference
ALL_TOOLS     := $(basename $(notdir $(wildcard tools/*.c)))
BAKE_TOOLS    := $(filter-out $(RUNTIME_TOOLS) $(BOTH_TOOLS),$(ALL_TOOLS))
BAKE_BINS     := $(addprefix $(BUILD)/bin/,$(BAKE_TOOLS))
RENDER_BINS   := $(addprefix $(BUILD)/bin/,$(filter dermis-render,$(ALL_TOOLS)))
BOTH_BINS     := $(addprefix $(BUILD)/bin/,$(filter $(BOTH_TOOLS),$(ALL_TOOLS)))

# The viewer (dermis-view): C objects, the ImGui adapter (C++), and Debian's ImGui GLFW and
# OpenGL3 backends compiled from the sources libimgui-dev ships (never copied into the repo).
# Built only where libimgui-dev (optional in scripts/deps.sh) is installed.
IMGUI_SRC    ?= /usr/share/doc/libimgui-dev/examples/backends
IMGUI_CFLAGS := -I/usr/include/imgui -I/usr/include/imgui/backends
IMGUI_LIBS   := $(shell $(PKG) --libs imgui 2>/dev/null)
VIEW_BIN     := $(if $(wildcard /usr/include/imgui/imgui.h),$(BUILD)/bin/dermis-view)
VIEW_OBJ     := $(call obj,tools/dermis-view.c $(sort $(wildcard tools/view/*.c tools/view/*.cpp))) \
                $(BUILD)/obj/imgui/imgui_impl_glfw.cpp.o $(BUILD)/obj/imgui/imgui_impl_opengl3.cpp.o

UNIT_TESTS   := $(patsubst tests/unit/%.c,$(BUILD)/tests/unit/%,$(wildcard tests/unit/*.c))
RENDER_TESTS := $(patsubst tests/render/%.c,$(BUILD)/tests/render/%,$(wildcard tests/render/*.c))
BENCHES      := $(patsubst bench/%.c,$(BUILD)/bench/%,$(wildcard bench/*.c))
# tests/view/: Criterion binaries that drive dermis-view under xvfb-run (scripts/run-tests.sh)
VIEW_TESTS   := $(if $(VIEW_BIN),$(patsubst tests/view/%.c,$(BUILD)/tests/view/%,$(wildcard tests/view/*.c)))

.PHONY: all test run-tests bench demo gallery reference deps clean fuzz tools docs install install-files uninstall
all: tools docs $(UNIT_TESTS) $(RENDER_TESTS) $(VIEW_TESTS) $(BENCHES)
tools: $(BAKE_BINS) $(RENDER_BINS) $(BOTH_BINS) $(VIEW_BIN)

# --- objects -----------------------------------------------------------------------
$(call obj,$(CORE_SRC)): $(BUILD)/obj/%.o: %
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(CORE_CFLAGS) -c $< -o $@
# Scenes look for assets missing beside them in --assets, DERMIS_ASSETS, then this default.
$(BUILD)/obj/lib/core/dm_scene_paths.c.o: CPPFLAGS += -DDM_ASSETS_DEFAULT='"$(abspath $(ASSETS))"'
$(call obj,$(filter %.c,$(BAKE_SRC))): $(BUILD)/obj/%.o: %
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(CORE_CFLAGS) $(BAKE_CFLAGS) -c $< -o $@
$(call obj,$(filter %.cpp,$(BAKE_SRC))): $(BUILD)/obj/%.o: %
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(CORE_CFLAGS) $(BAKE_CFLAGS) -c $< -o $@
$(BUILD)/obj/lib/render/%.c.o: lib/render/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(CORE_CFLAGS) -c $< -o $@
$(BUILD)/obj/lib/host/%.c.o: lib/host/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@
$(SHADER_GEN): $(SHADERS) scripts/embed-shaders.sh
	@mkdir -p $(@D)
	bash scripts/embed-shaders.sh $(SHADERS) > $@.tmp && mv $@.tmp $@
$(BUILD)/obj/gen/dm_shaders_gen.c.o: $(SHADER_GEN)
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) -c $< -o $@
$(BUILD)/obj/tools/%.c.o: tools/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(CORE_CFLAGS) -c $< -o $@
$(BUILD)/obj/tools/view/%.cpp.o: tools/view/%.cpp
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) $(IMGUI_CFLAGS) -c $< -o $@
# third-party code: no warnings, and no UBSan (1.86's GL loader indexes past its own array)
$(BUILD)/obj/imgui/%.cpp.o: $(IMGUI_SRC)/%.cpp
	@mkdir -p $(@D)
	$(CXX) $(CPPFLAGS) $(CXXFLAGS) -w -fno-sanitize=undefined $(IMGUI_CFLAGS) -c $< -o $@
$(BUILD)/obj/tests/%.c.o: tests/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) $(CFLAGS) $(CORE_CFLAGS) $(TEST_CFLAGS) -DDERMIS_ASSETS='"$(abspath $(ASSETS))"' \
	  -DDERMIS_BIN='"$(abspath $(BUILD)/bin)"' -c $< -o $@
$(BUILD)/obj/bench/%.c.o: bench/%.c
	@mkdir -p $(@D)
	$(CC) $(CPPFLAGS) -Ibench $(CFLAGS) $(CORE_CFLAGS) -DDERMIS_ASSETS='"$(abspath $(ASSETS))"' -c $< -o $@

# --- libraries ---------------------------------------------------------------------
$(CORE_LIB): $(call obj,$(CORE_SRC))
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^
$(BAKE_LIB): $(call obj,$(BAKE_SRC))
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^
$(RENDER_LIB): $(call obj,$(RENDER_SRC)) $(BUILD)/obj/gen/dm_shaders_gen.c.o
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^
$(HOST_LIB): $(call obj,$(HOST_SRC))
	@mkdir -p $(@D)
	rm -f $@ && ar rcs $@ $^

# --- executables (the offline side links with g++ for the C++ adapters) -------------
# A tool's own objects before the archives: make lists a prerequisite from another rule (a
# tool's command line, below) after the archives, where the linker would no longer look back.
link_order = $(filter %.o,$^) $(filter-out %.o,$^)
$(BAKE_BINS): $(BUILD)/bin/%: $(BUILD)/obj/tools/%.c.o $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(BAKE_LIBS) $(CORE_LIBS) -o $@
$(RENDER_BINS): $(BUILD)/bin/%: $(BUILD)/obj/tools/%.c.o $(RENDER_LIB) $(HOST_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) $(link_order) $(OSMESA_LIBS) $(CORE_LIBS) -lz -o $@
$(BOTH_BINS): $(BUILD)/bin/%: $(BUILD)/obj/tools/%.c.o $(RENDER_LIB) $(HOST_LIB) $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $(link_order) $(OSMESA_LIBS) $(BAKE_LIBS) $(CORE_LIBS) -o $@
# dermis-reference's and dermis-render's command lines live beside them (tools/ref/,
# tools/render/), linked before the libraries
$(BUILD)/bin/dermis-reference: $(call obj,$(sort $(wildcard tools/ref/*.c)))
$(BUILD)/bin/dermis-render: $(call obj,$(sort $(wildcard tools/render/*.c)))
# The viewer takes the physical skin model from the offline archive (its live sliders,
# bake/dm_skin_weights.h): plain C over core, so no offline third-party library is linked or
# loaded (check-layers.sh's link rule reads the binary).
$(VIEW_BIN): $(VIEW_OBJ) $(RENDER_LIB) $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(IMGUI_LIBS) $(GLFW_LIBS) $(CORE_LIBS) -lz -o $@
$(VIEW_TESTS): $(BUILD)/tests/view/%: $(BUILD)/obj/tests/view/%.c.o $(CORE_LIB) | $(VIEW_BIN) $(RENDER_BINS) $(BAKE_BINS) $(BOTH_BINS)
	@mkdir -p $(@D)
	$(CC) $(LDFLAGS) $^ $(CORE_LIBS) $(TEST_LIBS) -lz -o $@
$(UNIT_TESTS): $(BUILD)/tests/unit/%: $(BUILD)/obj/tests/unit/%.c.o $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(BAKE_LIBS) $(CORE_LIBS) $(TEST_LIBS) -o $@
$(RENDER_TESTS): $(BUILD)/tests/render/%: $(BUILD)/obj/tests/render/%.c.o $(RENDER_LIB) $(HOST_LIB) $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(OSMESA_LIBS) $(BAKE_LIBS) $(CORE_LIBS) $(TEST_LIBS) -o $@
$(BENCHES): $(BUILD)/bench/%: $(BUILD)/obj/bench/%.c.o $(RENDER_LIB) $(HOST_LIB) $(BAKE_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	$(CXX) $(LDFLAGS) $^ $(OSMESA_LIBS) $(BAKE_LIBS) $(CORE_LIBS) -o $@

# --- man pages, completions, install ---------------------------------------------------
# Made at build time from what they describe, so they cannot drift: section 1 by help2man
# from each tool's --help and --version (scripts/gen-man.sh), section 5 by go-md2man from the
# format docs (docs/dermis-*.5.md), completions from --help (scripts/gen-completion.sh).
VERSION     := $(shell sed -n 's/^\#define DM_VERSION "\(.*\)"/\1/p' lib/core/dm_version.h)
SOURCE_DATE_EPOCH ?= $(shell git log -1 --format=%ct 2>/dev/null)
export SOURCE_DATE_EPOCH
TOOL_BINS   := $(BAKE_BINS) $(RENDER_BINS) $(BOTH_BINS) $(VIEW_BIN)
TOOL_NAMES  := $(notdir $(TOOL_BINS))
MAN1        := $(patsubst %,$(BUILD)/share/man/man1/%.1,$(TOOL_NAMES))
MAN5_SRC    := $(sort $(wildcard docs/*.5.md))
MAN5        := $(patsubst docs/%.md,$(BUILD)/share/man/man5/%,$(MAN5_SRC))
COMPLETIONS := $(patsubst %,$(BUILD)/share/bash-completion/completions/%,$(TOOL_NAMES))
docs: $(MAN1) $(MAN5) $(COMPLETIONS)
$(BUILD)/share/man/man1/%.1: $(BUILD)/bin/% scripts/gen-man.sh scripts/man-common.h2m
	@mkdir -p $(@D)
	bash scripts/gen-man.sh $< > $@.tmp && mv $@.tmp $@
$(BUILD)/share/man/man5/%: docs/%.md
	@mkdir -p $(@D)
	{ echo '% $(basename $*) 5 "" "dermis $(VERSION)" "dermis file formats"'; cat $<; } > $@.md.tmp
	go-md2man -in $@.md.tmp -out $@.tmp && rm -f $@.md.tmp && mv $@.tmp $@
$(BUILD)/share/bash-completion/completions/%: $(BUILD)/bin/% scripts/gen-completion.sh scripts/help-options.sh
	@mkdir -p $(@D)
	bash scripts/gen-completion.sh $< > $@.tmp && mv $@.tmp $@

# make install [PREFIX=/usr/local] [DESTDIR=]: DESTDIR prefixes every installed path and is
# never compiled in. Headers keep lib/'s folders under
# include/dermis/ (Cflags -I$(includedir)/dermis, so "pack/dm_pack.h" reads as in the
# sources); the *_impl.h and *_internal.h headers and C++-only ones are not installed.
# Runtime (dermis.pc: pack reader + renderer) never names OpenEXR, OpenImageIO, OpenMesh or
# Embree; the offline bakers are dermis-bake.pc. Static libraries only: their third-party
# libraries are in Requires.private/Libs.private (pkg-config --static --libs).
PREFIX      ?= /usr/local
DESTDIR     ?=
BINDIR      ?= $(PREFIX)/bin
LIBDIR      ?= $(PREFIX)/lib
INCLUDEDIR  ?= $(PREFIX)/include
DATADIR     ?= $(PREFIX)/share
MANDIR      ?= $(DATADIR)/man
COMPDIR     ?= $(DATADIR)/bash-completion/completions
PCDIR       ?= $(LIBDIR)/pkgconfig
DOCDIR      ?= $(DATADIR)/doc/dermis
PRIVATE_H   := $(wildcard lib/*/*_impl.h lib/*/*_internal.h) lib/mesh/dm_mesh_gltf.h
LIB_DIRS    := $(CORE_DIRS) render host $(OFFLINE_DIRS)
PUBLIC_H    := $(filter-out $(PRIVATE_H),$(sort $(foreach d,$(LIB_DIRS),$(wildcard lib/$(d)/*.h))))
EXAMPLES    := $(wildcard examples/embed/*.c examples/embed/Makefile examples/embed/README.md)
INSTALL_LIBS := $(CORE_LIB) $(RENDER_LIB) $(HOST_LIB) $(BAKE_LIB)
# The .pc files are relocatable (as Meson's pkgconfig.relocatable): prefix is found from the
# file's own place (${pcfiledir}) when PCDIR lies under PREFIX, so a staged tree (DESTDIR)
# builds against its own headers and libraries with PKG_CONFIG_PATH alone; libdir and
# includedir follow prefix when they lie under it.
PC_PREFIX     := $(if $(filter $(PREFIX)/%,$(PCDIR)),$${pcfiledir}/$(shell realpath -m --relative-to=$(PCDIR) $(PREFIX)),$(PREFIX))
PC_LIBDIR     := $(patsubst $(PREFIX)/%,$${prefix}/%,$(LIBDIR))
PC_INCLUDEDIR := $(patsubst $(PREFIX)/%,$${prefix}/%,$(INCLUDEDIR))
# The libraries a sanitizer build needs at link time travel in the .pc files (a sanitize
# install is for testing dermis itself).
SAN_LIBS    := $(if $(filter sanitize,$(config)),$(filter -fsanitize=%,$(OPT)))

install: deps
	@$(MAKE) --no-print-directory -j$(NPROC) tools docs $(INSTALL_LIBS)
	@$(MAKE) --no-print-directory install-files

install-files:
	install -d $(DESTDIR)$(BINDIR) $(DESTDIR)$(LIBDIR) $(DESTDIR)$(PCDIR) $(DESTDIR)$(MANDIR)/man1 \
	  $(DESTDIR)$(MANDIR)/man5 $(DESTDIR)$(COMPDIR) $(DESTDIR)$(DATADIR)/dermis/scenes \
	  $(DESTDIR)$(DOCDIR)/examples/embed $(addprefix $(DESTDIR)$(INCLUDEDIR)/dermis/,$(LIB_DIRS))
	install -m 755 $(TOOL_BINS) $(DESTDIR)$(BINDIR)
	install -m 644 $(INSTALL_LIBS) $(DESTDIR)$(LIBDIR)
	$(foreach d,$(LIB_DIRS),install -m 644 $(filter lib/$(d)/%,$(PUBLIC_H)) $(DESTDIR)$(INCLUDEDIR)/dermis/$(d) &&) true
	install -m 644 $(MAN1) $(DESTDIR)$(MANDIR)/man1
	$(if $(MAN5),install -m 644 $(MAN5) $(DESTDIR)$(MANDIR)/man5)
	install -m 644 $(COMPLETIONS) $(DESTDIR)$(COMPDIR)
	install -m 644 assets/scenes/*.json $(DESTDIR)$(DATADIR)/dermis/scenes
	$(if $(EXAMPLES),install -m 644 $(EXAMPLES) $(DESTDIR)$(DOCDIR)/examples/embed)
	$(foreach pc,dermis dermis-osmesa dermis-bake,sed -e 's|@PREFIX@|$(PC_PREFIX)|; s|@LIBDIR@|$(PC_LIBDIR)|' \
	  -e 's|@INCLUDEDIR@|$(PC_INCLUDEDIR)|; s|@VERSION@|$(VERSION)|; s|@SAN_LIBS@|$(SAN_LIBS)|' \
	  scripts/pkgconfig/$(pc).pc.in > $(DESTDIR)$(PCDIR)/$(pc).pc &&) true

# Removes what install-files installed (the same lists; the shared folders it may have made,
# such as bin/ or man1/, stay).
uninstall:
	rm -f $(addprefix $(DESTDIR)$(BINDIR)/,$(ALL_TOOLS)) $(addprefix $(DESTDIR)$(LIBDIR)/,$(notdir $(INSTALL_LIBS))) \
	  $(addprefix $(DESTDIR)$(PCDIR)/,dermis.pc dermis-osmesa.pc dermis-bake.pc) \
	  $(addprefix $(DESTDIR)$(MANDIR)/man1/,$(addsuffix .1,$(ALL_TOOLS))) \
	  $(addprefix $(DESTDIR)$(MANDIR)/man5/,$(notdir $(MAN5_SRC:.md=))) \
	  $(addprefix $(DESTDIR)$(COMPDIR)/,$(ALL_TOOLS))
	rm -rf $(DESTDIR)$(INCLUDEDIR)/dermis $(DESTDIR)$(DATADIR)/dermis $(DESTDIR)$(DOCDIR)

# --- entry points ------------------------------------------------------------------
deps:
	@bash scripts/deps.sh

# The entry points build and run in sub-makes: this make parsed the Makefile before deps.sh
# installed anything, so what depends on installed packages (the viewer and its tests,
# pkg-config flags) is only right in a make started after it.
test: deps
	@$(MAKE) --no-print-directory -j$(NPROC) all
	@$(MAKE) --no-print-directory run-tests

run-tests:
	@FUZZ_SECONDS=$(FUZZ_SECONDS) NPROC=$(NPROC) MAKE="$(MAKE)" bash scripts/run-fuzz.sh $(notdir $(FUZZ_TARGETS)); fz=$$?; \
	  BUILD=$(BUILD) ASSETS=$(ASSETS) FUZZ_FAILED=$$fz bash scripts/run-tests.sh $(UNIT_TESTS) $(RENDER_TESTS) $(VIEW_TESTS)

bench: deps
	@$(MAKE) --no-print-directory -j$(NPROC) all
	@BUILD=$(BUILD) ASSETS=$(ASSETS) bash scripts/run-bench.sh $(BENCHES)

demo: deps
	@$(MAKE) --no-print-directory -j$(NPROC) tools
	@BUILD=$(BUILD) ASSETS=$(ASSETS) bash scripts/demo.sh

# The head at six skin parameter sets (albedo_from "skin") → docs/gallery.png, and the presets'
# profiles and spectra plotted → docs/skin-profiles.png, docs/skin-spectra.png.
gallery: deps
	@$(MAKE) --no-print-directory -j$(NPROC) tools
	@BUILD=$(BUILD) ASSETS=$(ASSETS) bash scripts/gallery.sh

# The head's texture-space ground truth in tiles through GNU parallel (REF_SIZE, REF_TILES).
reference: deps
	@$(MAKE) --no-print-directory -j$(NPROC) tools
	@BUILD=$(BUILD) ASSETS=$(ASSETS) bash scripts/reference.sh

# libFuzzer targets (clang): fuzz/NAME.c + the core library, built with ASan and UBSan. Each
# source is compiled once for all targets (build/fuzz/obj/, coverage-instrumented with
# fuzzer-no-link); a target links its own file with the sources it reads.
FUZZ_CC      ?= clang
FUZZ_CXX     ?= clang++
FUZZ_SECONDS ?= 5
FUZZ_TARGETS := $(patsubst fuzz/%.c,build/fuzz/%,$(wildcard fuzz/*.c))
FUZZ_SAN     := -g -O1 -fsanitize=address,undefined -fno-sanitize-recover=undefined -pthread -D_POSIX_C_SOURCE=200809L
fuzz_obj      = $(patsubst %,build/fuzz/obj/%.o,$(1))
fuzz: $(FUZZ_TARGETS)
build/fuzz/obj/%.c.o: %.c
	@mkdir -p $(@D)
	$(FUZZ_CC) -std=c11 $(FUZZ_SAN) -fsanitize=fuzzer-no-link -MMD -MP -Ilib -Itools/view $(CORE_CFLAGS) \
	  $(if $(filter lib/image/% lib/mesh/%,$<),$(BAKE_CFLAGS)) -c $< -o $@
build/fuzz/obj/%.cpp.o: %.cpp
	@mkdir -p $(@D)
	$(FUZZ_CXX) -std=c++17 $(FUZZ_SAN) -fsanitize=fuzzer-no-link -MMD -MP -w -Ilib $(BAKE_CFLAGS) -c $< -o $@
build/fuzz/%: build/fuzz/obj/fuzz/%.c.o $(call fuzz_obj,$(CORE_SRC))
	$(FUZZ_CC) $(FUZZ_SAN) -fsanitize=fuzzer $^ $(CORE_LIBS) -o $@
# fuzz_script: the viewer's script reader (C, no window) beside the core library.
build/fuzz/fuzz_script: $(call fuzz_obj,tools/view/dm_viewer_script.c)
# fuzz_bake_exr: the offline EXR reader (OpenEXR's C API) beside the core library.
build/fuzz/fuzz_bake_exr: $(call fuzz_obj,lib/image/dm_exr.c)
build/fuzz/fuzz_bake_exr: CORE_LIBS += -lOpenEXRCore-3_1
# Targets that read meshes (fuzz_gltf, fuzz_obj): also the mesh loaders (C and C++), linked
# with OpenMesh and tinygltf by clang++.
FUZZ_MESH      := build/fuzz/fuzz_gltf build/fuzz/fuzz_obj
FUZZ_MESH_SRC  := $(addprefix lib/mesh/,dm_isolate.c dm_mesh.c dm_mesh_check.c dm_mesh_gpu.c dm_mesh_gltf.cpp dm_mesh_openmesh.cpp)
$(FUZZ_MESH): build/fuzz/%: build/fuzz/obj/fuzz/%.c.o $(call fuzz_obj,$(CORE_SRC) $(FUZZ_MESH_SRC))
	$(FUZZ_CXX) $(FUZZ_SAN) -fsanitize=fuzzer $^ $(shell $(PKG) --libs openmesh tinygltf 2>/dev/null) $(CORE_LIBS) -o $@

clean:
	rm -rf build

-include $(shell find $(BUILD)/obj build/fuzz/obj -name '*.d' 2>/dev/null)
