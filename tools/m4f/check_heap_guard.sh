#!/usr/bin/env bash
# Negative test of the firmware heap guard: links tiny programs exactly like the ECU image
# (same compiler flags, linker script, start-up, --wrap options) and checks that
#   1. a program without allocation links (so a failure below is the guard, not the set-up);
#   2. a direct malloc() call fails the link, naming the caller (--wrap=malloc);
#   3. a C library function that allocates internally (snprintf -> _malloc_r) fails the link
#      (--wrap=_malloc_r, naming the library member);
#   4. the same without any --wrap option still fails, on the linker-script ASSERT of
#      cm4f_sections.ld alone (the second, independent layer).
# Usage: check_heap_guard.sh CC "CFLAGS" LD_DIR LD_SCRIPT STARTUP_LIB GUARD_OPTION...
set -uo pipefail
cc=$1 cflags=$2 lddir=$3 ldscript=$4 startup=$5
shift 5
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'int main(void) { return 0; }\n' >"$work/ok.c"
printf '#include <stdlib.h>\nint main(void) { return malloc(16) != 0; }\n' >"$work/direct.c"
printf '#include <stdio.h>\nint main(void) { char b[16]; return snprintf(b, sizeof b, "%%d", 7); }\n' >"$work/indirect.c"
link() { # source log guard-options...
  local src=$1 log=$2
  shift 2
  # shellcheck disable=SC2086
  "$cc" $cflags -O2 -nostartfiles --specs=nano.specs -T "$ldscript" -L "$lddir" -Wl,--gc-sections \
    -Wl,--require-defined=g_vector_table "$@" "$work/$src.c" "$startup" -o "$work/$log.elf" \
    >"$work/$log.log" 2>&1
}
fail=0
for name in ok direct indirect assert; do
  if [ "$name" = assert ]; then link indirect assert; else link "$name" "$name" "$@"; fi
  rc=$?
  case $name in
    ok) if ((rc == 0)); then echo "  heap guard: a program without allocation links                            ok"
        else echo "  heap guard: FAILED, the allocation-free probe does not link:"; cat "$work/$name.log"; fail=1; fi ;;
    direct) if ((rc != 0)) && grep -q "__wrap_malloc" "$work/$name.log"; then
          echo "  heap guard: malloc() in our code fails the link (--wrap), naming the caller ok"
        else echo "  heap guard: FAILED, a malloc() call linked"; cat "$work/$name.log"; fail=1; fi ;;
    indirect) if ((rc != 0)) && grep -q "__wrap__malloc_r" "$work/$name.log"; then
          echo "  heap guard: malloc inside the C library (snprintf) fails the link (--wrap)   ok"
        else echo "  heap guard: FAILED, snprintf's allocator linked"; cat "$work/$name.log"; fail=1; fi ;;
    assert) if ((rc != 0)) && grep -q "heap use is forbidden" "$work/$name.log"; then
          echo "  heap guard: the same without --wrap fails on the linker-script ASSERT          ok"
        else echo "  heap guard: FAILED, the linker-script ASSERT did not fire"; cat "$work/$name.log"; fail=1; fi ;;
  esac
done
exit $fail
