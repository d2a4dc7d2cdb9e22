#!/bin/sh
# The sanitizer build stops at a double cast beyond uint32's range: exit non-zero, with UBSan's message.
# Usage: SanitizerCanaryTest.sh SANITIZER_CANARY
set -u
output=$("$1" 4294967297 2>&1)
status=$?
echo "$output"
if [ "$status" -eq 0 ]; then
    echo "FAIL: the cast of 4294967297 to uint32 ran on (exit 0): float-cast-overflow is off or recoverable"
    exit 1
fi
if ! echo "$output" | grep -q "outside the range of representable values"; then
    echo "FAIL: exit $status without UBSan's float-cast-overflow message"
    exit 1
fi
echo "OK: exit $status with UBSan's message"
