#include "util/error.hpp"
#include "util/json.hpp"

#include <catch2/catch.hpp>
#include <cmath>

using imgmesh::Json;

TEST_CASE("Json keeps insertion order and round-trips through parse") {
  Json j = Json::object();
  j["zeta"] = 1;
  j["alpha"] = 2.5;
  j["name"] = "a \"quoted\"\nline";
  j["list"] = std::vector<int>{3, 1, 2};
  j["nested"]["ok"] = true;
  const std::string text = j.dump(-1);
  REQUIRE(text.find("\"zeta\"") < text.find("\"alpha\""));
  Json back = Json::parse(text);
  REQUIRE(back.keys() == j.keys());
  CHECK(back.at("zeta").integer() == 1);
  CHECK(back.at("alpha").number() == 2.5);
  CHECK(back.at("name").string() == "a \"quoted\"\nline");
  REQUIRE(back.at("list").items().size() == 3);
  CHECK(back.at("list").items()[2].integer() == 2);
  CHECK(back.at("nested").at("ok").boolean());
  CHECK(Json::parse(j.dump(2)).dump(-1) == text);
}

TEST_CASE("Json writes non-finite numbers as null and rejects bad text") {
  Json j = Json::object();
  j["x"] = std::nan("");
  CHECK(j.dump(-1) == "{\"x\":null}");
  CHECK_THROWS_AS(Json::parse("{\"a\":}"), imgmesh::Error);
  CHECK_THROWS_AS(Json::parse("[1,2"), imgmesh::Error);
  CHECK_THROWS_AS(Json::parse("{} x"), imgmesh::Error);
}
