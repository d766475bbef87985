// The studio's 3D view: a QOpenGLWidget hosting a VTK render window.
//
// VTK draws into its own framebuffers inside the widget's OpenGL context and paintGL copies the result
// into Qt's framebuffer (the recipe and its traps are in shared/docs/qt6-vtk.md). Camera: trackball;
// left drag rotates, middle drag or Shift+left drag pans, right drag or the wheel zooms, Ctrl+left drag
// spins around the view axis.
//
// Besides meshes it shows heat map scenes (buildScalarScene): scalars colour-mapped with viridis over
// [0, scalarRange()], a scalar bar, and the value under the cursor (scalarHovered). A compare scene
// splits the view: the compare scene left of the split position, the scene right of it, both in the
// same camera (a swipe between the original and a level). An overlay scene (the structure's cells) is
// drawn as coloured lines over whatever is shown. Markers (numbered points, e.g. landmarks) are drawn as
// spheres with their labels over the scene.
#pragma once

#include "lodforge/widgets/ViewOptions.h"

#include <QColor>
#include <QOpenGLWidget>
#include <QString>

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace lodforge::widgets {

class MeshScene;

// A point drawn over the scene (model coordinates) as a sphere of a few pixels with a text label.
struct ViewMarker {
    std::array<double, 3> position{};
    QString label;
    QColor color;
};

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

    // From now on this view uses `source`'s camera: moving either moves both (connect cameraChanged to
    // the other views' update()). nullptr gives the view a camera of its own again.
    void setSharedCamera(VtkView* source);

    // Heat map scenes: the value mapped to the top of the colour map (<= 0: the scene's largest value).
    void setScalarRange(double maximum);
    double scalarRange() const;
    void setScalarBarVisible(bool visible);
    // The scalar of the surface under `position` (widget coordinates), interpolated from the vertices of
    // the picked triangle; nothing when no heat map surface is there.
    std::optional<double> scalarAt(QPoint position);

    // Split compare: `reference` (nullptr: none) drawn left of splitPosition, the scene right of it.
    void setCompareScene(std::shared_ptr<const MeshScene> reference);
    const std::shared_ptr<const MeshScene>& compareScene() const;
    void setSplitPosition(double fraction);  // 0 = left edge, 1 = right edge
    double splitPosition() const;

    // A cells overlay (buildCellsScene; nullptr: none) drawn as lines over the scene while the view
    // options ask for cells, coloured by depth or triangle count as they say. Not picked, not framed by
    // resetView.
    void setOverlayScene(std::shared_ptr<const MeshScene> overlay);
    const std::shared_ptr<const MeshScene>& overlayScene() const;
    // Whether an overlay is drawn now (a scene is set and the options show cells).
    bool overlayVisible() const;

    // The silhouette of `outline` (the original, for a level's heat map; nullptr: none) as lines over the
    // scene, seen from the current camera: where the level's outline left the original's shows. Not
    // picked, not framed.
    void setOutlineScene(std::shared_ptr<const MeshScene> outline);
    const std::shared_ptr<const MeshScene>& outlineScene() const;

    // The camera (shared or own) in model units; setViewCamera moves it and emits cameraChanged.
    struct ViewCamera {
        std::array<double, 3> position{0, 0, 1};
        std::array<double, 3> focalPoint{0, 0, 0};
        std::array<double, 3> viewUp{0, 1, 0};
        double viewAngle = 30;  // vertical field of view, degrees
    };
    ViewCamera viewCamera() const;
    void setViewCamera(const ViewCamera& camera);

    // Markers over the scene (replacing the previous ones; empty: none). Not picked, not framed.
    void setMarkers(const std::vector<ViewMarker>& markers);
    std::size_t markerCount() const;
    // The point of the scene's surface under `position` (widget coordinates), in model coordinates;
    // nothing where no surface is.
    std::optional<std::array<double, 3>> surfacePointAt(QPoint position);

    // Frames rendered since construction; tests and screenshots wait for it to move.
    quint64 frameCount() const;

    QSize sizeHint() const override;

signals:
    void frameRendered();
    // The camera moved through this view (interaction, resetView): views sharing it must repaint.
    void cameraChanged();
    // The heat map value under the mouse; hoverLeft when the cursor leaves the surface.
    void scalarHovered(double value);
    void hoverLeft();
    // A left click without a drag (press and release within a few pixels), widget coordinates.
    void clicked(QPoint position);

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
    void updateSplitPlanes();
    void pickHover();

    struct Private;
    std::unique_ptr<Private> d;
};

}  // namespace lodforge::widgets
