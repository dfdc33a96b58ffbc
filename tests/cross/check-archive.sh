#!/usr/bin/env bash
# Checks of a cross-built firmware archive, run by ctest on the build machine.
#   check-archive.sh symbols ARCHIVE NM NUMERIC PROCESSOR
#       no heap and no stdio among the undefined symbols; on the ATmega fixed
#       build, no soft-float routine either (fixed-point is the point there)
#   check-archive.sh stack OBJDIR TARGET
#       every function's stack frame is static (-fstack-usage); prints the largest
#   check-archive.sh size ARCHIVE SIZE TARGET
#       prints text/data/bss of the archive
set -euo pipefail

symbols() {
    local archive=$1 nm=$2 numeric=$3 processor=$4
    local undefined
    undefined=$("$nm" -u "$archive" | awk 'NF >= 2 && $1 == "U" { print $2 } NF == 1 && $1 !~ /:$/ { print $1 }' | sort -u)
    local forbidden='^_*(malloc|calloc|realloc|free|_malloc_r|_free_r|_calloc_r|_realloc_r|printf|fprintf|sprintf|snprintf|vprintf|vfprintf|vsprintf|vsnprintf|puts|fputs|putchar|fputc|fwrite|fopen|fclose|fflush|_impure_ptr|stdout|stderr|__iob)$'
    local bad
    bad=$(grep -E "$forbidden" <<<"$undefined" || true)
    if [ "$processor" = avr ] && [ "$numeric" = fixed ]; then
        # avr-libc's float routines: __addsf3, __mulsf3, __fixsfsi, __ltsf2, ... and libm's
        bad+=$(grep -E '^__[a-z]+sf[0-9]?$|^__[a-z]+sf[a-z]+$|^__fp_|^(sqrt|sin|cos|tan|atan|atan2|asin|acos|exp|log|pow)f?$' <<<"$undefined" || true)
    fi
    echo "undefined symbols of $(basename "$archive") ($processor, $numeric): $(wc -w <<<"$undefined")"
    tr '\n' ' ' <<<"$undefined"; echo
    if [ -n "$bad" ]; then
        echo "FORBIDDEN: $bad"
        return 1
    fi
    echo "no heap, no stdio$([ "$processor" = avr ] && [ "$numeric" = fixed ] && echo ', no soft-float')"
}

stack() {
    local objdir=$1 target=$2
    local files
    files=$(find "$objdir" -name '*.su' | sort)
    if [ -z "$files" ]; then
        echo "no .su files under $objdir (was -fstack-usage given?)"
        return 1
    fi
    # lines: file:line:col:function<TAB>bytes<TAB>static|dynamic|dynamic,bounded
    local not_static
    not_static=$(awk -F'\t' '$3 != "static"' $files)
    echo "functions: $(cat $files | wc -l)"
    # The last awk reads all of sort's output (no `head`): under pipefail, a
    # reader that exits early can kill sort with SIGPIPE and fail the check.
    awk -F'\t' '{ n = split($1, p, ":"); print $2 "\t" p[n] }' $files | sort -rn |
        awk -v t="$target" -F'\t' 'NR == 1 { printf "largest stack frame (%s): %s bytes in %s\n", t, $1, $2 } NR > 1 && NR <= 5 { printf "  next: %s bytes in %s\n", $1, $2 }'
    if [ -n "$not_static" ]; then
        echo "NOT STATIC:"; echo "$not_static"
        return 1
    fi
    echo "every frame is static"
}

size_of() {
    local archive=$1 size=$2 target=$3
    "$size" -t "$archive" | awk -v t="$target" 'END { printf "library size (%s): text %d, data %d, bss %d bytes\n", t, $1, $2, $3 }'
}

case "${1:-}" in
symbols) shift; symbols "$@" ;;
stack) shift; stack "$@" ;;
size) shift; size_of "$@" ;;
*) echo "usage: $0 symbols|stack|size ..." >&2; exit 2 ;;
esac
