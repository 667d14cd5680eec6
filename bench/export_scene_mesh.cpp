// Writes a scene's tessellated patches (exactly the triangles the path tracer and the solver see) as
// one ASCII PLY per material, plus materials.json naming each file with its ρ_d and emission, so
// that another renderer (bench_reference_vs_mitsuba.py) can load the very same geometry.
// Usage: export_scene_mesh SCENE.json OUTDIR
#include <hr/geometry.h>
#include <hr/scene.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s SCENE.json OUTDIR\n", argv[0]);
    return 2;
  }
  try {
    hr::Scene scene = hr::loadScene(argv[1]);
    hr::TessellationReport rep;
    std::vector<hr::Patch> patches = hr::buildPatches(scene, rep);
    std::filesystem::path out(argv[2]);
    std::filesystem::create_directories(out);
    nlohmann::json mats = nlohmann::json::array();
    for (std::uint32_t m = 0; m < scene.materials.size(); ++m) {
      std::vector<const hr::Patch*> mine;
      for (const hr::Patch& p : patches)
        if (p.material == m) mine.push_back(&p);
      if (mine.empty()) continue;
      std::size_t tris = 0;
      for (const hr::Patch* p : mine) tris += std::size_t(p->poly.n - 2);
      std::string file = "material_" + std::to_string(m) + ".ply";
      std::ofstream f(out / file);
      // Unshared corners: every triangle keeps its own face normal wherever the loader puts normals.
      f << "ply\nformat ascii 1.0\nelement vertex " << 3 * tris << "\nproperty float x\nproperty float y\n"
        << "property float z\nelement face " << tris << "\nproperty list uchar int vertex_indices\nend_header\n";
      f.precision(9);
      for (const hr::Patch* p : mine)
        for (int k = 1; k + 1 < p->poly.n; ++k)
          for (int j : {0, k, k + 1}) f << p->poly.v[j].x << ' ' << p->poly.v[j].y << ' ' << p->poly.v[j].z << '\n';
      for (std::size_t t = 0; t < tris; ++t) f << "3 " << 3 * t << ' ' << 3 * t + 1 << ' ' << 3 * t + 2 << '\n';
      const hr::Material& mat = scene.materials[m];
      mats.push_back({{"name", mat.name},
                      {"ply", file},
                      {"diffuse", {mat.diffuse.x, mat.diffuse.y, mat.diffuse.z}},
                      {"specular", {mat.specular.x, mat.specular.y, mat.specular.z}},
                      {"emission", {mat.emission.x, mat.emission.y, mat.emission.z}},
                      {"triangles", tris}});
    }
    std::ofstream(out / "materials.json") << mats.dump(2) << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
