/* sscs plugin ABI, version 1: the C interface between sscs and a plugin (a shared object in a
 * plugin folder). Only C types cross it: no C++ types, no exceptions (plugin.hpp wraps it for
 * C++ authors and catches exceptions before they reach sscs).
 *
 * A plugin exports two functions:
 *   uint32_t sscs_plugin_abi_version(void);               -- returns SSCS_PLUGIN_ABI_VERSION
 *   int sscs_plugin_register(const sscs_host* host);      -- registers its classes; 0 on success
 * sscs calls sscs_plugin_abi_version first and refuses a plugin built for another version.
 *
 * Constraint classes (the report's "functional constraints"): a `plugin` constraint in a vault
 * names a class, the participating attributes (references such as Room1.height) and free-form
 * args; sscs passes the attribute values (in the file units: m, deg, kg, s) and the args as JSON
 * to the class's check, which answers pass or fail, a margin (how far from violation, positive
 * when satisfied, in `unit`) and a message.
 */
#ifndef SSCS_PLUGIN_H
#define SSCS_PLUGIN_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define SSCS_PLUGIN_ABI_VERSION 1u

#if defined(__GNUC__)
#define SSCS_PLUGIN_EXPORT __attribute__((visibility("default")))
#else
#define SSCS_PLUGIN_EXPORT
#endif

/* What a check answers. sscs zero-fills it before the call. */
typedef struct sscs_check_result {
  int pass;            /* 1: satisfied, 0: violated */
  double margin;       /* positive when satisfied; a NaN margin is reported as an error */
  char unit[16];       /* the margin's unit ("m", "deg", "" for a plain number) */
  char message[512];   /* what the report prints; on an error, what went wrong */
} sscs_check_result;

/* One participating attribute, in the order the vault lists them. */
typedef struct sscs_value {
  const char* ref;     /* as written: "Room1.height" */
  double value;        /* in the file unit of its dimension */
  const char* unit;    /* "m", "deg", "kg", "s" or "" */
} sscs_value;

/* Returns 0 when it could evaluate (result->pass says the outcome), nonzero on an error (with
 * result->message saying why): then the constraint's status is `error`. */
typedef int (*sscs_check_fn)(void* user, const sscs_value* values, size_t count, const char* args_json,
                             sscs_check_result* result);

typedef struct sscs_constraint_class {
  const char* name;          /* the `class:` a vault names; letters, digits, _ and - */
  const char* description;
  size_t min_values;         /* how many attributes it needs ... */
  size_t max_values;         /* ... (SIZE_MAX: any number) */
  sscs_check_fn check;
  void* user;                /* passed back to check */
} sscs_constraint_class;

/* What sscs offers a registering plugin. `size` is sizeof(sscs_host) in the sscs that calls:
 * later versions only add members at the end. Strings are copied; they need not outlive the call. */
typedef struct sscs_host {
  uint32_t abi_version;
  uint32_t size;
  void* context;
  /* Returns 0, or nonzero when the class is rejected (a bad name, a name already taken). */
  int (*add_constraint_class)(void* context, const sscs_constraint_class* cls);
  /* Reports why registration fails (printed with the plugin's path). */
  void (*error)(void* context, const char* message);
} sscs_host;

typedef uint32_t (*sscs_plugin_abi_version_fn)(void);
typedef int (*sscs_plugin_register_fn)(const sscs_host* host);

#ifdef __cplusplus
}
#endif

#endif /* SSCS_PLUGIN_H */
