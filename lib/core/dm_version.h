/* dm_version.h — the one version string every tool and output file carries. */
#ifndef DM_VERSION_H
#define DM_VERSION_H
#define DM_VERSION "0.1.0"
#endif
