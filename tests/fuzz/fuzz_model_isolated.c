/* libFuzzer harness: fuzz_model's inputs through persp-import, the isolated
 * importer persp uses by default. What it proves is containment: whatever
 * the readers do with an input (crash, loop, allocate without bound), this
 * process gets a status and a one-line detail and goes on; and persp's
 * side checks every record of the importer's answer. Its corpus holds
 * inputs that crash the readers in a process of their own (deep nesting,
 * self-instancing, declared counts of billions), which fuzz_model cannot
 * replay. */
#define FUZZ_IMPORT PERSP_MODEL_IMPORT_ISOLATED
#include "fuzz_model.c"
