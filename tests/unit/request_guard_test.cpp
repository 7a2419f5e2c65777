// The API's cross-site guard (daemon/api/request_guard.hpp): what a foreign page, a
// DNS-rebinding page, the overlay page and the rig CLI each send, and what rigd answers.
#include <gtest/gtest.h>

#include "auth.hpp"
#include "request_guard.hpp"

namespace rig::api {
namespace {

Request post(const std::string& host, const std::string& origin, const std::string& content_type) {
  Request r{http::verb::post, "/api/home", 11};
  if (!host.empty()) r.set(http::field::host, host);
  if (!origin.empty()) r.set(http::field::origin, origin);
  if (!content_type.empty()) r.set(http::field::content_type, content_type);
  r.body() = "{}";
  return r;
}

Request get(const std::string& host, const std::string& target = "/api/status") {
  Request r{http::verb::get, target, 11};
  r.set(http::field::host, host);
  return r;
}

const RequestGuard kGuard("https://rig07.lab.example:8443, http://bench-pc:8080", "rigbox");

TEST(RequestGuard, TheOverlayPageCommandingItsOwnRigdIsAccepted) {
  EXPECT_FALSE(
      kGuard.refusal(post("127.0.0.1:8080", "http://127.0.0.1:8080", "application/json"), true));
  EXPECT_FALSE(kGuard.refusal(
      post("localhost:8080", "http://localhost:8080", "application/json; charset=utf-8"), true));
  EXPECT_FALSE(kGuard.refusal(post("[::1]:8080", "http://[::1]:8080", "application/json"), true));
}

TEST(RequestGuard, TheCliWithoutAnOriginHeaderIsAccepted) {
  EXPECT_FALSE(kGuard.refusal(post("127.0.0.1", "", "application/json"), true));
}

TEST(RequestGuard, APageOfAnotherOriginCannotCommandTheRig) {
  const auto why =
      kGuard.refusal(post("127.0.0.1:8080", "http://evil.example", "application/json"), true);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("evil.example"), std::string::npos) << *why;
  // Another port on loopback is another origin too (any local web app).
  EXPECT_TRUE(
      kGuard.refusal(post("127.0.0.1:8080", "http://127.0.0.1:3000", "application/json"), true));
  EXPECT_TRUE(kGuard.refusal(post("127.0.0.1:8080", "null", "application/json"), true));
}

TEST(RequestGuard, ATextPlainOrFormPostIsRefusedEvenWithoutOrigin) {
  for (const char* type :
       {"text/plain", "application/x-www-form-urlencoded", "multipart/form-data; boundary=x", ""}) {
    const auto why = kGuard.refusal(post("127.0.0.1:8080", "", type), true);
    ASSERT_TRUE(why) << type;
    EXPECT_NE(why->find("application/json"), std::string::npos) << *why;
  }
}

TEST(RequestGuard, ADnsRebindingPageIsRefusedForReadsToo) {
  const auto why = kGuard.refusal(get("attacker.example:8080"), false);
  ASSERT_TRUE(why);
  EXPECT_NE(why->find("attacker.example"), std::string::npos) << *why;
  EXPECT_TRUE(kGuard.refusal(
      post("attacker.example:8080", "http://attacker.example:8080", "application/json"), true));
  EXPECT_TRUE(kGuard.refusal(get(""), false)) << "no Host at all";
}

TEST(RequestGuard, TheMachinesOwnNameAndConfiguredOriginsAreAccepted) {
  EXPECT_FALSE(kGuard.refusal(get("rigbox:8080"), false));
  EXPECT_FALSE(kGuard.refusal(get("RIGBOX.local:8080"), false));
  EXPECT_FALSE(kGuard.refusal(
      post("rig07.lab.example:8443", "https://rig07.lab.example:8443", "application/json"), true));
  // A configured origin may command a rigd reached under another of its names.
  EXPECT_FALSE(
      kGuard.refusal(post("192.168.1.7:8080", "http://bench-pc:8080", "application/json"), true));
  EXPECT_TRUE(
      kGuard.refusal(post("192.168.1.7:8080", "http://bench-pc:9999", "application/json"), true));
}

TEST(RequestGuard, WebSocketUpgradesFromAForeignPageAreRefused) {
  Request upgrade = get("127.0.0.1:8080", "/ws");
  EXPECT_FALSE(kGuard.upgrade_refusal(upgrade)) << "no Origin: a program, not a page";
  upgrade.set(http::field::origin, "http://127.0.0.1:8080");
  EXPECT_FALSE(kGuard.upgrade_refusal(upgrade));
  upgrade.set(http::field::origin, "http://evil.example");
  EXPECT_TRUE(kGuard.upgrade_refusal(upgrade));
}

TEST(RequestGuard, HostNamesSplitFromTheirPorts) {
  EXPECT_EQ(host_without_port("Example.COM:80"), "example.com");
  EXPECT_EQ(host_without_port("[::1]:8080"), "[::1]");
  EXPECT_EQ(host_without_port("[::1]"), "[::1]");
  EXPECT_EQ(host_without_port("10.0.0.1"), "10.0.0.1");
}

TEST(ApiAuth, ABase64TokenSentUrlEncodedOnTheWebSocketUrlIsAccepted) {
  const std::string token = "ab+/cd==EF0123456789";
  const ApiAuth auth(token);
  Request ws = get("127.0.0.1:8080", "/ws?token=ab%2B%2Fcd%3D%3DEF0123456789");
  EXPECT_TRUE(auth.authorized(ws));
  Request wrong = get("127.0.0.1:8080", "/ws?token=ab%2B%2Fcd%3D%3DEF0123456780");
  EXPECT_FALSE(auth.authorized(wrong));
  Request raw = get("127.0.0.1:8080", "/ws?token=ab+/cd==EF0123456789");
  EXPECT_TRUE(auth.authorized(raw)) << "an unencoded token still works";
}

}  // namespace
}  // namespace rig::api
