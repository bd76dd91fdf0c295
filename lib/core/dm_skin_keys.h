/* dm_skin_keys.h — the names of the physical skin's parameters, as a scene file and the
 * tools' --skin give them (the one list: the scene reader in core checks them, the model
 * in bake (bake/dm_skin_spec.h) maps them to its parameters and ranges).
 *
 * In order: melanin, eumelanin, blood (the required three), oxygenation, epidermis-mm,
 * dermis-mm, eta. "preset" is not among them: it names a starting point (a scene's
 * {"skin": {"preset": …}}, a tool's --skin-preset). */
#ifndef DM_SKIN_KEYS_H
#define DM_SKIN_KEYS_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

enum { DM_SKIN_KEY_COUNT = 7, DM_SKIN_KEY_REQUIRED_COUNT = 3, DM_SKIN_PRESET_NAME_SIZE = 32 };

extern const char *const dm_skin_keys[DM_SKIN_KEY_COUNT];

/* The index of the key of len bytes at key (not NUL-terminated there), or −1. */
int dm_skin_key_index(const char *key, size_t len);

/* "melanin, eumelanin, blood, oxygenation, epidermis-mm, dermis-mm or eta", for messages. */
const char *dm_skin_keys_text(void);

#ifdef __cplusplus
}
#endif
#endif
