// `glossyhr info SCENE`: what a scene (JSON or MGF) holds.
#pragma once
#include <string>

int runInfo(const std::string& scene, bool json);
