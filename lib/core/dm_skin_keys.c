/* dm_skin_keys.c — the skin parameters' names (dm_skin_keys.h). */
#include "core/dm_skin_keys.h"

#include <string.h>

const char *const dm_skin_keys[DM_SKIN_KEY_COUNT] = {"melanin",      "eumelanin", "blood", "oxygenation",
                                                     "epidermis-mm", "dermis-mm", "eta"};

int dm_skin_key_index(const char *key, size_t len)
{
    for (int k = 0; k < DM_SKIN_KEY_COUNT; ++k)
        if (strlen(dm_skin_keys[k]) == len && !strncmp(key, dm_skin_keys[k], len)) return k;
    return -1;
}

const char *dm_skin_keys_text(void)
{
    return "melanin, eumelanin, blood, oxygenation, epidermis-mm, dermis-mm or eta";
}
