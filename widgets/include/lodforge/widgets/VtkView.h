// The studio's 3D view: a QOpenGLWidget hosting a VTK render window.
//
// VTK draws into its own framebuffers inside the widget's OpenGL context and paintGL copies the result
// into Qt's framebuffer (the recipe and its traps are in shared/docs/qt6-vtk.md). Camera: trackball;
// left drag rotates, middle drag or Shift+left drag pans, right drag or the wheel zooms, Ctrl+left drag
// spins around the view axis.
#pragma once

#include "lodforge/widgets/ViewOptions.h"

#include <QOpenGLWidget>

#include <memory>

namespace lodforge::widgets {

class MeshScene;

class VtkView : public QOpenGLWidget {
    Q_OBJECT

public:
    explicit VtkView(QWidget* parent = nullptr);
    ~VtkView() override;

    // VTK needs an OpenGL 3.2 core context with a depth buffer. Call before the QApplication is created.
    static void setDefaultSurfaceFormat();

    // Shows `scene` (nullptr: nothing). With resetCamera the camera frames the new scene, otherwise the
    // current viewpoint is kept.
    void setScene(std::shared_ptr<const MeshScene> scene, bool resetCamera = true);
    const std::shared_ptr<const MeshScene>& scene() const;

    void setViewOptions(const ViewOptions& options);
    const ViewOptions& viewOptions() const;

    // Frames the scene from the default viewpoint: Y up, from the -Z side turned 35 degrees about Y and
    // 15 degrees from above.
    void resetView();

    // Frames rendered since construction; tests and screenshots wait for it to move.
    quint64 frameCount() const;

    QSize sizeHint() const override;

signals:
    void frameRendered();

protected:
    void initializeGL() override;
    void paintGL() override;
    void resizeGL(int width, int height) override;

    void mousePressEvent(QMouseEvent* event) override;
    void mouseReleaseEvent(QMouseEvent* event) override;
    void mouseMoveEvent(QMouseEvent* event) override;
    void mouseDoubleClickEvent(QMouseEvent* event) override;
    void wheelEvent(QWheelEvent* event) override;
    void enterEvent(QEnterEvent* event) override;
    void leaveEvent(QEvent* event) override;

private:
    void releaseGraphics();
    void applyViewOptions();

    struct Private;
    std::unique_ptr<Private> d;
};

}  // namespace lodforge::widgets
