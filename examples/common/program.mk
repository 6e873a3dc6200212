# What the example programs' Makefiles share: PROGRAM (set before including this) is built
# from PROGRAM.c against arbor's static library (cargo build --release first, or set
# ARBOR_LIB to another build directory) and GLFW and libpng from pkg-config.
ARBOR_ROOT ?= ../..
ARBOR_LIB ?= $(ARBOR_ROOT)/target/release
CFLAGS ?= -O2 -g
CFLAGS += -std=c11 -Wall -Wextra -Werror -I$(ARBOR_ROOT)/include $(shell pkg-config --cflags glfw3 libpng)
LDLIBS += $(ARBOR_LIB)/libarbor.a $(shell pkg-config --libs glfw3 libpng) -lm -lpthread -ldl

$(PROGRAM): $(PROGRAM).c $(ARBOR_ROOT)/examples/common/glapp.h $(ARBOR_ROOT)/include/arbor.h $(ARBOR_LIB)/libarbor.a
	$(CC) $(CFLAGS) -o $@ $(PROGRAM).c $(LDLIBS)

run: $(PROGRAM)
	./$(PROGRAM)

clean:
	rm -f $(PROGRAM)

.PHONY: run clean
