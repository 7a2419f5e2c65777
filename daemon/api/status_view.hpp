#pragma once
// The loop's status as the API's Status message, and as Prometheus metrics.
#include <string>

#include "api_context.hpp"

namespace rig::api {

std::string status_json(ApiContext& context);
std::string prometheus_metrics(ApiContext& context);

}  // namespace rig::api
