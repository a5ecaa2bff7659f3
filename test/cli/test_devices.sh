# test_devices.sh: `strandlight devices` and `strandlight kernels`, device selection (--device),
# the no-ICD case, kernel location (STRANDLIGHT_KERNELS) and build failures.
. test/cli/lib.sh
export SL_CACHE_DIR="$TMP/devices-cache"

expect_output devices_help "usage: strandlight devices" "$SL" devices --help
expect_output kernels_help "usage: strandlight kernels" "$SL" kernels --help
out=$("$SL" devices --bogus 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass devices_bad_arg_is_usage_error; else fail devices_bad_arg_is_usage_error "rc=$rc $out"; fi

# devices: exit 0 and a verdict for auto, whatever is installed.
expect_output devices_lists "auto: " "$SL" devices

# No OpenCL ICD at all: clGetPlatformIDs gives -1001 (toolchain.md sec. 2).
expect_output devices_no_icd "no OpenCL platforms (" env OCL_ICD_VENDORS=/nonexistent "$SL" devices
expect_output devices_no_icd_auto_is_c "auto: C path" env OCL_ICD_VENDORS=/nonexistent "$SL" devices
expect_error kernels_no_icd_pocl "no OpenCL platforms" env OCL_ICD_VENDORS=/nonexistent "$SL" kernels --device pocl
expect_error kernels_no_icd_gpu "--device gpu: no GPU OpenCL device" env OCL_ICD_VENDORS=/nonexistent "$SL" kernels --device gpu
expect_error kernels_no_icd_opencl "--device opencl" env OCL_ICD_VENDORS=/nonexistent "$SL" kernels --device opencl
# auto without OpenCL: the C path, said on stderr, and kernels has nothing to compare (exit 0).
out=$(OCL_ICD_VENDORS=/nonexistent "$SL" kernels 2>&1); rc=$?
if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "strandlight: device: C path (no OpenCL platforms" &&
   printf '%s' "$out" | grep -q "SKIP"; then pass kernels_no_icd_auto_falls_back_to_c
else fail kernels_no_icd_auto_falls_back_to_c "rc=$rc $out"; fi

expect_error kernels_bad_device "--device 'nonsense'" "$SL" kernels --device nonsense
expect_error kernels_no_such_index "--device 77:0: no such OpenCL device" "$SL" kernels --device 77:0
expect_output kernels_device_c "SKIP" "$SL" kernels --device c
out=$("$SL" kernels --only nosuch 2>&1); rc=$?
if [ $rc -eq 2 ]; then pass kernels_unknown_check_is_usage_error; else fail kernels_unknown_check_is_usage_error "rc=$rc $out"; fi
expect_output kernels_list "prefix_sum" "$SL" kernels --list

# On the test device ($SL_CL_DEVICE, test/cli/lib.sh): every kernel matches its C twin; the
# program comes from the disk cache next time.
if have_cl; then
    expect_output kernels_cl_pass "prefix_sum " "$SL" kernels --device "$SL_CL_DEVICE" --reps 1
    out=$("$SL" kernels --device "$SL_CL_DEVICE" --reps 1 2>&1); rc=$?
    if [ $rc -eq 0 ] && ! printf '%s' "$out" | grep -q FAIL && printf '%s' "$out" | grep -q "0 built from source"; then
        pass kernels_cl_all_pass_from_cache
    else fail kernels_cl_all_pass_from_cache "rc=$rc $out"; fi
    if ls "$SL_CACHE_DIR" | grep -q '^prefix_sum-.*\.bin$'; then pass kernels_cache_written; else fail kernels_cache_written "no entry in $SL_CACHE_DIR"; fi
    no_leftovers kernels_cache_no_temp_files "$SL_CACHE_DIR"
    # auto announces its choice and why on stderr, in one line.
    err=$("$SL" kernels --only prefix_sum --reps 1 2>&1 >/dev/null)
    if printf '%s' "$err" | grep -q "^strandlight: device: .*(.*)$"; then pass kernels_auto_says_why
    else fail kernels_auto_says_why "$err"; fi

    # A kernel dir whose prefix_sum.cl does not compile: the build log on stderr, exit 1.
    broken="$TMP/broken-kernels"; rm -rf "$broken"; mkdir -p "$broken"
    cp kernels/*.h kernels/*.cl "$broken"/; cp kernels/*.inc "$broken"/ 2>/dev/null
    echo 'this is not OpenCL C;' >> "$broken/prefix_sum.cl"
    out=$(STRANDLIGHT_KERNELS="$broken" "$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum 2>&1); rc=$?
    if [ $rc -eq 1 ] && printf '%s' "$out" | grep -q "OpenCL build failed" &&
       printf '%s' "$out" | grep -q "^strandlight: prefix_sum.cl: "; then pass kernels_build_failure_reported
    else fail kernels_build_failure_reported "rc=$rc $out"; fi
    out=$(STRANDLIGHT_KERNELS=/nonexistent/kernels "$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum 2>&1); rc=$?
    if [ $rc -eq 1 ] && printf '%s' "$out" | grep -q "STRANDLIGHT_KERNELS=/nonexistent/kernels: not a directory"; then
        pass kernels_missing_kernel_dir
    else fail kernels_missing_kernel_dir "rc=$rc $out"; fi
    # A corrupt cache entry is ignored and rebuilt.
    for f in "$SL_CACHE_DIR"/prefix_sum-*.bin; do printf 'garbage' > "$f"; done
    out=$("$SL" kernels --device "$SL_CL_DEVICE" --only prefix_sum --reps 1 2>&1); rc=$?
    if [ $rc -eq 0 ] && printf '%s' "$out" | grep -q "1 built from source"; then pass kernels_corrupt_cache_rebuilt
    else fail kernels_corrupt_cache_rebuilt "rc=$rc $out"; fi
else
    skip kernels_cl_pass "no OpenCL device"
fi
