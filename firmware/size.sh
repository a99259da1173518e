#!/bin/sh
# size.sh ELF NAME FLASH_MAX RAM_MAX: print an image's flash and RAM use
# (flash = .text + .data, RAM = .data + .bss + .noinit) and fail over budget.
set -e
elf=$1 name=$2 flash_max=$3 ram_max=$4
set -- $(avr-size -A "$elf" | awk '$1==".text"{t=$2} $1==".data"{d=$2} $1==".bss"{b=$2}
                                 $1==".noinit"{n=$2} END{print t+d, d+b+n}')
flash=$1 ram=$2
echo "$name: flash $flash of $flash_max bytes budgeted, RAM $ram of $ram_max (.data+.bss+.noinit)"
if [ "$flash" -gt "$flash_max" ] || [ "$ram" -gt "$ram_max" ]; then
    echo "$name: over budget" >&2
    exit 1
fi
