// Builds against an installed nephele through find_package(nephele) from C++: the package config
// imports nephele::api (libnephele.so.0 + include/nephele/nephele.h), the only installed interface
// (issue 17: no internal module headers or static libraries are installed).
#include <nephele/nephele.h>

#include <cstdio>

int main() {
  const auto* api = static_cast<const nph_api_v2*>(nph_get_api(NPH_API_VERSION));
  if (api == nullptr || api->version != NPH_API_VERSION || api->struct_size != sizeof(nph_api_v2)) {
    std::fprintf(stderr, "consumer: nph_get_api(%u) gave no matching table\n", NPH_API_VERSION);
    return 1;
  }
  nph_dataset* ds = nullptr;
  if (api->dataset_open("/nonexistent.nph", &ds) != NPH_ERROR_INPUT || ds != nullptr) return 1;
  std::printf("consumer: libnephele %s, API version %u\n", api->library_version(), api->version);
  return 0;
}
