// PLACEHOLDER until the tricycle tests land (this session).
#include <catch2/catch.hpp>
