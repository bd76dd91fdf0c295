/* Available memory and the refusal every tool shares (core/dm_memory.h): the override for
 * tests, /proc/meminfo, the message with both numbers. */
#include <criterion/criterion.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/dm_memory.h"

Test(memory, override_in_mib)
{
    setenv(DM_MEMORY_ENV, "123", 1);
    dm_memory_available a;
    dm_memory_available_get(&a);
    cr_expect_eq(a.size, (uint64_t)123 << 20);
    cr_expect_str_eq(a.source, "DERMIS_MEM_AVAILABLE_MB");
    dm_error err = {0};
    cr_expect_eq(dm_memory_check((uint64_t)100 << 20, "x", NULL, NULL, &err), DM_OK);
    cr_expect_eq(dm_memory_check((uint64_t)200 << 20, "the renderer at 64x36", "texture space 150 MiB", "lower --size",
                                 &err),
                 DM_ERR_OUT_OF_MEMORY);
    cr_expect_str_eq(err.detail, "the renderer at 64x36 needs about 200 MiB of memory (texture space 150 MiB), more than "
                                 "the 123 MiB available (DERMIS_MEM_AVAILABLE_MB): lower --size");
    unsetenv(DM_MEMORY_ENV);
}

Test(memory, a_bad_override_is_ignored_and_meminfo_read)
{
    const char *bad[] = {"", "abc", "-5", "12x", "99999999999999999999"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        setenv(DM_MEMORY_ENV, bad[i], 1);
        dm_memory_available a;
        dm_memory_available_get(&a);
        cr_expect_str_neq(a.source, "DERMIS_MEM_AVAILABLE_MB", "'%s' taken", bad[i]);
        /* Linux: MemAvailable (or a cgroup's limit), a plausible amount */
        cr_expect(a.size > ((uint64_t)16 << 20) && a.size < ((uint64_t)1 << 50), "%s: %llu", a.source,
                  (unsigned long long)a.size);
    }
    unsetenv(DM_MEMORY_ENV);
}

Test(memory, size_text_and_peak)
{
    char t[32];
    dm_memory_size_text((uint64_t)812 << 20, t, sizeof t);
    cr_expect_str_eq(t, "812 MiB");
    dm_memory_size_text((uint64_t)19800 << 20, t, sizeof t);
    cr_expect_str_eq(t, "19.3 GiB");
    dm_memory_size_text(2048, t, sizeof t);
    cr_expect_str_eq(t, "2 KiB");
    cr_expect_gt(dm_memory_peak_rss(), (uint64_t)1 << 20);
}
