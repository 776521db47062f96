// A studio HTTP module built for another ABI of strata (the next one): its
// entry refuses this strata, as the module of another build does
// (src/studio/http_module_entry.cpp). tests/studio_module_missing.cmake puts
// it beside a strata to see that strata say so.
#include "studio/http_module.h"

extern "C" __attribute__((visibility("default"))) strata::studio::HttpServer* strata_studio_http_server(
    int abi, std::size_t /*options_size*/, const strata::studio::StudioOptions& /*options*/,
    strata::studio::EventHub& /*hub*/) {
  if (abi != strata::studio::kHttpModuleAbi + 1) return nullptr;
  return nullptr;  // never reached by this strata; a real module would make its server
}
