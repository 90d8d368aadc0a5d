#!/bin/sh
# geoscni post on a folder without results.h5 exits 2 and says what is
# missing; on a folder that does not exist likewise.
geoscni="$1"
folder=$(mktemp -d /tmp/geoscni-test-post-cli-XXXXXX)
failures=0
for target in "$folder" "$folder/absent"; do
    "$geoscni" post "$target" --no-pictures >"$folder.out" 2>&1
    status=$?
    if [ "$status" -ne 2 ]; then
        echo "FAIL: geoscni post $target exited $status, expected 2"
        failures=$((failures + 1))
    fi
    if ! grep -q "results.h5 not found" "$folder.out"; then
        echo "FAIL: the message does not say results.h5 is missing:"
        failures=$((failures + 1))
    fi
    cat "$folder.out"
done
rm -rf "$folder" "$folder.out"
exit $failures
