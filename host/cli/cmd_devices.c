/* cmd_devices.c: `strandlight devices`: every OpenCL platform and device with the facts that
 * matter here, and which one `--device auto` would choose. */
#include "cl/clrt.h"
#include "cli/cli.h"

#include <stdio.h>

static void usage(FILE *fp) {
    fprintf(fp, "usage: strandlight devices\n\n"
                "Lists OpenCL platforms and devices (type, compute units, clock, memory, OpenCL C\n"
                "version, fp64, gl_sharing, images) and marks with '*' the device that\n"
                "--device auto picks (GPU, else PoCL CPU, else the C path).\n"
                "Device names for --device: auto, gpu, pocl, opencl, c, P:D (platform:device\n"
                "as listed) or N (the #N index).\n"
                "Exit status 0 even when there is no OpenCL platform.\n");
}

static void print_bytes(cl_ulong b) {
    const char *unit[] = {"B", "KiB", "MiB", "GiB", "TiB"};
    double v = (double)b;
    int u = 0;
    while (v >= 1024 && u < 4)
        v /= 1024, u++;
    printf("%.*f %s", u ? 2 : 0, v, unit[u]);
}

int cmd_devices(int argc, char **argv) {
    for (int i = 1; i < argc; i++) {
        if (cli_is_help(argv[i])) {
            usage(stdout);
            return 0;
        }
        return cli_usage_error("devices", "unexpected argument '%s'", argv[i]);
    }
    sl_cl_inventory inv;
    sl_cl_inventory_get(&inv);
    char why[1024];
    int pick = sl_cl_inventory_auto(&inv, why, sizeof why);
    if (inv.num_platforms == 0) {
        if (inv.platform_err != CL_SUCCESS)
            printf("no OpenCL platforms (clGetPlatformIDs returned %s (%d)%s)\n",
                   sl_cl_strerror(inv.platform_err), (int)inv.platform_err,
                   inv.platform_err == -1001 ? ": no OpenCL driver (ICD) is installed, or "
                                               "OCL_ICD_VENDORS points nowhere"
                                             : "");
        else
            printf("no OpenCL platforms (the OpenCL loader found none)\n");
    }
    for (int p = 0; p < inv.num_platforms; p++) {
        const sl_cl_platinfo *pl = &inv.platforms[p];
        printf("platform %d: %s (%s)%s\n", p, pl->name, pl->version, pl->is_pocl ? " [PoCL]" : "");
        if (pl->num_devices == 0)
            printf("  no devices (clGetDeviceIDs returned %s (%d)); skipped\n",
                   sl_cl_strerror(pl->device_err), (int)pl->device_err);
        for (int i = 0; i < inv.num_devices; i++) {
            const sl_cl_devinfo *d = &inv.devices[i];
            if (d->platform_index != p) continue;
            printf("%s device %d:%d (#%d): %s%s\n", i == pick ? "*" : " ", p, d->device_index,
                   d->global_index, d->name, i == pick ? "   <- auto" : "");
            printf("    type %s, %u compute units, %u MHz, max work-group %zu\n",
                   sl_cl_type_name(d->type), d->compute_units, d->max_clock_mhz, d->max_work_group);
            printf("    global memory ");
            print_bytes(d->global_mem);
            printf(", local memory ");
            print_bytes(d->local_mem);
            printf(", max allocation ");
            print_bytes(d->max_alloc);
            printf("\n    %s, driver %s\n", d->opencl_c_version, d->driver_version);
            printf("    fp64 %s, gl_sharing %s, images %s\n", d->fp64 ? "yes" : "no",
                   d->gl_sharing ? "yes" : "no", d->images ? "yes" : "no");
        }
    }
    if (pick >= 0) {
        char label[512];
        sl_cl_device_label(&inv.devices[pick], label, sizeof label);
        printf("auto: %d:%d %s (%s)\n", inv.devices[pick].platform_index,
               inv.devices[pick].device_index, label, why);
    } else {
        printf("auto: C path (%s)\n", why);
    }
    sl_cl_inventory_free(&inv);
    return 0;
}
