// The entry point of libstrata_studio_http.so (http_module.h).
#include "studio/http_module.h"
#include "studio/server.h"

extern "C" __attribute__((visibility("default"))) strata::studio::HttpServer* strata_studio_http_server(
    int abi, std::size_t options_size, const strata::studio::StudioOptions& options, strata::studio::EventHub& hub) {
  if (abi != strata::studio::kHttpModuleAbi || options_size != sizeof(strata::studio::StudioOptions)) return nullptr;
  return new strata::studio::StudioServer(options, hub);
}
