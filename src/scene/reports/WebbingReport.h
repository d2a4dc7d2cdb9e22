#pragma once
/// The webbing report of a run: the places where the sheet lies on itself at the end (core/Webbing.h), as
/// OUT/webbing.csv (one line per place, the largest first) and summary.json's "webbing".

#include "scene/Scene.h"

#include "core/contact/Webbing.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
/// Whether a run of this scene reports webbing: `report.webbing` if the scene gives it, else forming scenes (a
/// `forming` section or a material) and scenes with contact.self_collision.
bool reportsWebbing(const SceneSpec& spec);
/// How close two parts of the sheet must be to count as lying on each other: 1.5 contact radii (a self-contact holds
/// them one radius apart).
Real webbingDistance(const SceneSpec& spec);
/// The places where the scene's sheet lies on itself now.
std::vector<WebbingPlace> webbingPlaces(const Scene& scene);
/// One line per place: its size, where it is now (centre and box, m) and which part of the sheet it is (the box of
/// its masses' starting positions in x and z, m).
std::string webbingCsv(const std::vector<WebbingPlace>& places);
/// The count, the distance and the ten largest places, as in the CSV.
nlohmann::json webbingSummary(const std::vector<WebbingPlace>& places, Real distance);
} // namespace masse::scene
