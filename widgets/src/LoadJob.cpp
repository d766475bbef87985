#include "lodforge/widgets/LoadJob.h"

#include "lodforge/error.h"
#include "lodforge/io/image_decode.h"
#include "lodforge/io/mesh_io.h"
#include "lodforge/widgets/Job.h"
#include "lodforge/widgets/MeshScene.h"
#include "lodforge/widgets/QueuedProgress.h"

#include <QFile>
#include <QtConcurrent/QtConcurrentRun>

#include <map>
#include <string>

namespace lodforge::widgets {

namespace {

// Decodes the base colour texture of every material, each distinct image once. Problems (a missing or
// undecodable file) do not fail the load: the mesh is still worth seeing; they come back as warnings.
std::vector<std::shared_ptr<const Image>> decodeBaseColorTextures(const Mesh& mesh, QStringList& warnings,
                                                                  Progress* progress) {
    std::vector<std::shared_ptr<const Image>> images(mesh.materials.size());
    if (!mesh.has_texcoords()) return images;
    std::map<std::string, std::shared_ptr<const Image>> byFile;  // resolved path -> image
    const std::size_t count = mesh.materials.size();
    for (std::size_t m = 0; m < count; ++m) {
        check_progress(progress, static_cast<double>(m) / static_cast<double>(count), "Decoding textures");
        const TextureRef& texture = mesh.materials[m].base_color_texture;
        if (texture.empty()) continue;
        const std::string file = texture.bytes.empty() ? mesh.resolve_texture_path(texture) : std::string{};
        if (!file.empty()) {
            if (auto it = byFile.find(file); it != byFile.end()) {
                images[m] = it->second;
                continue;
            }
        }
        try {
            auto image = std::make_shared<const Image>(decode_texture(mesh, texture));
            images[m] = image;
            if (!file.empty()) byFile.emplace(file, image);
        } catch (const Error& e) {
            if (e.kind() == Error::Kind::cancelled) throw;
            warnings << QString::fromUtf8(e.what());
            if (!file.empty()) byFile.emplace(file, nullptr);
        }
    }
    check_progress(progress, 1.0, "Decoding textures");
    return images;
}

}  // namespace

LoadJob::LoadJob(QString path, QObject* parent) : QObject(parent), path_(std::move(path)) {
    progress_ = std::make_unique<QueuedProgress>(this, [this](double fraction, const QString& stage) {
        emit progressChanged(fraction, stage);
    });
    connect(&watcher_, &QFutureWatcher<LoadResult>::finished, this, [this] {
        // The future holds exactly one result: load() never throws.
        emit finished(watcher_.result());
    });
}

LoadJob::~LoadJob() {
    // The worker reports to this object: it must be done before the object goes.
    progress_->cancel();
    watcher_.waitForFinished();
}

void LoadJob::start() {
    if (watcher_.isRunning()) return;
    QueuedProgress* progress = progress_.get();
    watcher_.setFuture(QtConcurrent::run([path = path_, progress] { return load(path, progress); }));
}

void LoadJob::cancel() { progress_->cancel(); }

bool LoadJob::isRunning() const { return watcher_.isRunning(); }

LoadResult LoadJob::load(const QString& path, Progress* progress) {
    LoadResult result;
    result.path = path;
    auto model = std::make_shared<LoadedModel>();
    // Job::run catches everything the reader throws; its messages start with the path.
    const JobResult run = Job::run(path, [&](Progress* p) {
        model->path = path;
        const std::string file = QFile::encodeName(path).toStdString();
        ReadOptions read;
        read.place_every_instance = true;  // a viewer shows every placement of an instanced glTF mesh
        model->mesh = read_mesh(file, read, p);
        model->images = decodeBaseColorTextures(model->mesh, model->warnings, p);
        check_progress(p, 0.0, "Summarising");
        model->info = mesh_info(model->mesh, file, format_name(detect_format(file)));
        check_progress(p, 0.0, "Preparing the view");
        model->scene = buildMeshScene(model->mesh, model->images);
        check_progress(p, 1.0, "Preparing the view");
    }, progress);
    model->elapsedMs = run.elapsedMs;
    switch (run.status) {
    case JobResult::Status::ok:
        result.status = LoadResult::Status::ok;
        result.model = std::move(model);
        break;
    case JobResult::Status::cancelled: result.status = LoadResult::Status::cancelled; break;
    case JobResult::Status::failed: result.status = LoadResult::Status::failed; break;
    }
    result.error = run.error;
    return result;
}

}  // namespace lodforge::widgets
