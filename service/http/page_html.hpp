#pragma once
// The service's page at / (service/http/page.html, built into the binary): paste a token,
// upload a zipped swatch folder, start fits and watch them on their event streams, open the
// reports. Plain HTML, CSS and JavaScript; nothing is loaded from elsewhere.

namespace yarnfit::service {

[[nodiscard]] const char* page_html();

}  // namespace yarnfit::service
