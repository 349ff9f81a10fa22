<?xml version="1.0" encoding="utf-8"?>
<!DOCTYPE TS>
<TS version="2.1" language="zh_CN">
<context>
    <name>MainWindow</name>
    <message>
        <source>&amp;Save project</source>
        <translation>保存工程(&amp;S)</translation>
    </message>
    <message>
        <source>Save project &amp;as…</source>
        <translation>工程另存为(&amp;A)…</translation>
    </message>
    <message>
        <source>&amp;Close project</source>
        <translation>关闭工程(&amp;C)</translation>
    </message>
    <message>
        <source>Everything is saved as it happens in {0}: nothing to save (File ▸ Save project as… writes a copy under another name)</source>
        <translation>所有更改已随时保存在 {0}：无需保存（文件 ▸ 工程另存为… 可另存副本）</translation>
    </message>
    <message>
        <source>No project is open</source>
        <translation>没有打开的工程</translation>
    </message>
    <message>
        <source>Closed project {0}</source>
        <translation>已关闭工程 {0}</translation>
    </message>
    <message>
        <source>(from {0} steps of the decision log, undos and redos included)</source>
        <translation>（来自决策日志中的 {0} 步，含撤销与重做）</translation>
    </message>
    <message>
        <source>Main toolbar</source>
        <translation>主工具栏</translation>
    </message>
    <message>
        <source>the settings' pipeline stage {0} is not one of Run ▸ Pipeline stages (clean, compress, associate); dropped</source>
        <translation>设置中的流程步骤 {0} 不属于“运行 ▸ 流程步骤”（清洗、压缩、关联）；已舍弃</translation>
    </message>
    <message>
        <source>{0}, run again by itself for the decisions made while it ran, failed: its result is out of date (stale) and was not applied; run {0} again</source>
        <translation>{0} 因运行期间所做的决定而自动重新运行，但失败了：其结果已过时，未被采用；请重新运行 {0}</translation>
    </message>
    <message>
        <source>{0}: out of date, its re-run failed</source>
        <translation>{0}：结果已过时，自动重新运行失败</translation>
    </message>
    <message>
        <source>Pipeline loaded, not as written</source>
        <translation>流程已载入，但未按文件原样执行</translation>
    </message>
    <message>
        <source>Pipeline loaded, not as written ({0} changes, see the Log): runs {1}</source>
        <translation>流程已载入，但未按文件原样执行（{0} 处改动，见日志）：执行 {1}</translation>
    </message>
    <message>
        <source>Pipeline loaded: runs {0}</source>
        <translation>流程已载入：执行 {0}</translation>
    </message>
    <message>
        <source>Run ▸ pipeline runs its stages in the order {0}, not as the file has them ({1}): its stages have a fixed order (wakeline batch runs the file as written)</source>
        <translation>“运行 ▸ 流程”按 {0} 的顺序执行各步骤，而不是文件中的顺序（{1}）：其步骤顺序固定（wakeline batch 按文件原样执行）</translation>
    </message>
    <message>
        <source>the pipeline has no clean stage; Run ▸ pipeline cleans first all the same</source>
        <translation>流程中没有清洗步骤；“运行 ▸ 流程”仍会先清洗</translation>
    </message>
    <message>
        <source>the pipeline's maneuvers stage is run as Compress (maneuvers, then compress): Run ▸ pipeline has no maneuvers-only stage</source>
        <translation>流程中的机动步骤按压缩执行（先检测机动，再压缩）：“运行 ▸ 流程”没有单独的机动步骤</translation>
    </message>
    <message>
        <source>the pipeline's {0} stage comes {1} times; Run ▸ pipeline runs it once, with the parameters of the last</source>
        <translation>流程中的 {0} 步骤出现 {1} 次；“运行 ▸ 流程”只执行一次，使用最后一次的参数</translation>
    </message>
    <message>
        <source>the pipeline's {0} stage is not run by Run ▸ pipeline (clean, compress, associate); its parameters are loaded</source>
        <translation>流程中的 {0} 步骤不由“运行 ▸ 流程”执行（清洗、压缩、关联）；其参数已载入</translation>
    </message>
    <message>
        <source>Pipeline s&amp;tages</source>
        <translation>流程步骤(&amp;T)</translation>
    </message>
    <message>
        <source>&amp;Associate (one sensor; proposals to review)</source>
        <translation>单源关联(&amp;A)（生成待审核的候选建议）</translation>
    </message>
    <message>
        <source>&amp;Compress (maneuvers and compression)</source>
        <translation>压缩(&amp;C)（机动检测与压缩）</translation>
    </message>
    <message>
        <source>Run &amp;pipeline (clean)</source>
        <translation>运行流程(&amp;P)（清洗）</translation>
    </message>
    <message>
        <source>Run &amp;pipeline (clean, associate)</source>
        <translation>运行流程(&amp;P)（清洗、关联）</translation>
    </message>
    <message>
        <source>Run &amp;pipeline (clean, maneuvers, compress, associate)</source>
        <translation>运行流程(&amp;P)（清洗、机动检测、压缩、关联）</translation>
    </message>
    <message>
        <source>{0}: decisions made while it ran change the pairs it keeps out; it runs again with them</source>
        <translation>{0}：运行期间做出的决策改变了要排除的配对；将按这些决策重新运行</translation>
    </message>
    <message>
        <source>Clean</source>
        <translation>清洗</translation>
    </message>
    <message>
        <source>Compress</source>
        <translation>压缩</translation>
    </message>
    <message>
        <source>Associate</source>
        <translation>关联</translation>
    </message>
    <message>
        <source>Fuse</source>
        <translation>融合</translation>
    </message>
    <message>
        <source>Open bearings</source>
        <translation>打开方位数据</translation>
    </message>
    <message>
        <source>Review</source>
        <translation>审核</translation>
    </message>
    <message>
        <source>Open {0}</source>
        <translation>打开 {0}</translation>
    </message>
    <message>
        <source>{0} on {1}</source>
        <translation>对 {1} 运行{0}</translation>
    </message>
    <message>
        <source>quarantined {0:,}: {1}</source>
        <translation>隔离 {0:,} 行：{1}</translation>
    </message>
    <message>
        <source>quarantined {0:,}: {1} (line {2})</source>
        <translation>隔离 {0:,} 行：{1}（第 {2} 行）</translation>
    </message>
    <message>
        <source>quarantined {0:,}: {1} (lines {2})</source>
        <translation>隔离 {0:,} 行：{1}（第 {2} 行）</translation>
    </message>
    <message>
        <source>blanked {0:,} (row kept): {1}</source>
        <translation>清空 {0:,} 个值（保留该行）：{1}</translation>
    </message>
    <message>
        <source>Removed layer {0}; the review of {1} keeps the points its proposals were made on (in the project): its decisions stay</source>
        <translation>已移除图层 {0}；{1} 的审核保留了其候选建议所依据的点（保存在项目中）：其决定仍然有效</translation>
    </message>
    <message>
        <source>{0}, {1}</source>
        <translation>{0}，{1}</translation>
    </message>
    <message>
        <source>{0} · {1} of the tracks overlap the time window</source>
        <translation>{0} · 其中 {1} 条航迹的时间跨度与时间窗重叠</translation>
    </message>
    <message>
        <source>matching the filter</source>
        <translation>与筛选匹配</translation>
    </message>
    <message>
        <source>whose time span overlaps the time window</source>
        <translation>时间跨度与时间窗重叠</translation>
    </message>
    <message>
        <source>{0} of {1} tracks: those {2}</source>
        <translation>显示 {1} 条航迹中的 {0} 条：{2}的航迹</translation>
    </message>
    <message>
        <source>{0} of 1 track: those {1}</source>
        <translation>显示 1 条航迹中的 {0} 条：{1}的航迹</translation>
    </message>
    <message>
        <source> and </source>
        <translation>且</translation>
    </message>
    <message>
        <source>{0} runs on {1}</source>
        <translation>{0} 在 {1} 上运行</translation>
    </message>
    <message>
        <source>Wakeline</source>
        <translation>Wakeline 航迹工作台</translation>
    </message>
    <message>
        <source>&amp;Open tracks…</source>
        <translation>打开航迹(&amp;O)…</translation>
    </message>
    <message>
        <source>Open &amp;project…</source>
        <translation>打开工程(&amp;P)…</translation>
    </message>
    <message>
        <source>Open &amp;bearings (bearing-only detection)…</source>
        <translation>打开方位数据(&amp;B)（纯方位机动检测）…</translation>
    </message>
    <message>
        <source>Open bearings</source>
        <translation>打开方位数据</translation>
    </message>
    <message>
        <source>Active layer as &amp;CSV…</source>
        <translation>当前图层导出为 &amp;CSV…</translation>
    </message>
    <message>
        <source>Active layer as &amp;GeoJSON…</source>
        <translation>当前图层导出为 &amp;GeoJSON…</translation>
    </message>
    <message>
        <source>&amp;Maneuver points as CSV…</source>
        <translation>机动点导出为 CSV(&amp;M)…</translation>
    </message>
    <message>
        <source>&amp;Quit</source>
        <translation>退出(&amp;Q)</translation>
    </message>
    <message>
        <source>Run &amp;pipeline (clean, maneuvers, compress)</source>
        <translation>运行流程(&amp;P)（清洗、机动检测、压缩）</translation>
    </message>
    <message>
        <source>&amp;Clean</source>
        <translation>清洗(&amp;C)</translation>
    </message>
    <message>
        <source>&amp;Maneuvers</source>
        <translation>机动检测(&amp;M)</translation>
    </message>
    <message>
        <source>C&amp;ompress</source>
        <translation>压缩(&amp;O)</translation>
    </message>
    <message>
        <source>&amp;Associate (one sensor)</source>
        <translation>单源关联(&amp;A)</translation>
    </message>
    <message>
        <source>&amp;Fuse (several sensors)</source>
        <translation>多源融合(&amp;F)</translation>
    </message>
    <message>
        <source>Cancel the running job</source>
        <translation>取消正在运行的任务</translation>
    </message>
    <message>
        <source>&amp;Fit to data</source>
        <translation>缩放到数据(&amp;F)</translation>
    </message>
    <message>
        <source>&amp;Box zoom</source>
        <translation>框选缩放(&amp;B)</translation>
    </message>
    <message>
        <source>&amp;Time zone</source>
        <translation>时区(&amp;T)</translation>
    </message>
    <message>
        <source>&amp;UTC</source>
        <translation>协调世界时 UTC(&amp;U)</translation>
    </message>
    <message>
        <source>The zone the &amp;data came in (the import's time zone)</source>
        <translation>数据的时区(&amp;D)（导入时指定的时区）</translation>
    </message>
    <message>
        <source>This &amp;computer's zone</source>
        <translation>本机时区(&amp;C)</translation>
    </message>
    <message>
        <source>&amp;Remove active layer</source>
        <translation>移除当前图层(&amp;R)</translation>
    </message>
    <message>
        <source>&amp;Colour tracks of the active layer apart (up to 30 tracks)</source>
        <translation>当前图层按航迹分色(&amp;C)(至多 30 条航迹)</translation>
    </message>
    <message>
        <source>Dra&amp;w active layer as points (radar plots)</source>
        <translation>当前图层画成点(&amp;W)(雷达点迹)</translation>
    </message>
    <message>
        <source>… and {0} more tracks</source>
        <translation>… 另有 {0} 条航迹</translation>
    </message>
    <message>
        <source>… and {0} more selected</source>
        <translation>… 另有 {0} 条已选航迹</translation>
    </message>
    <message>
        <source>{0} · +{1} same colour</source>
        <translation>{0} · 另 {1} 条同色</translation>
    </message>
    <message>
        <source>removed: {0} ({1})</source>
        <translation>已删除：{0}（{1}）</translation>
    </message>
    <message>
        <source>Positions at {0}</source>
        <translation>位置时刻 {0}</translation>
    </message>
    <message>
        <source>Sh&amp;ow points removed by cleaning</source>
        <translation>显示清洗去除的点(&amp;O)</translation>
    </message>
    <message>
        <source>&amp;Import report and quarantined rows…</source>
        <translation>导入报告与隔离行(&amp;I)…</translation>
    </message>
    <message>
        <source>&amp;File</source>
        <translation>文件(&amp;F)</translation>
    </message>
    <message>
        <source>&amp;Export</source>
        <translation>导出(&amp;E)</translation>
    </message>
    <message>
        <source>&amp;Run</source>
        <translation>运行(&amp;R)</translation>
    </message>
    <message>
        <source>&amp;View</source>
        <translation>视图(&amp;V)</translation>
    </message>
    <message>
        <source>&amp;Language</source>
        <translation>语言(&amp;L)</translation>
    </message>
    <message>
        <source>Layers</source>
        <translation>图层</translation>
    </message>
    <message>
        <source>Parameters</source>
        <translation>参数</translation>
    </message>
    <message>
        <source>Batch table</source>
        <translation>批次表</translation>
    </message>
    <message>
        <source>Detail</source>
        <translation>详情</translation>
    </message>
    <message>
        <source>Statistics</source>
        <translation>统计</translation>
    </message>
    <message>
        <source>Log</source>
        <translation>日志</translation>
    </message>
    <message>
        <source>Filter batches (any column)…</source>
        <translation>筛选批次（任意列）…</translation>
    </message>
    <message>
        <source>Cancel</source>
        <translation>取消</translation>
    </message>
    <message>
        <source>Sensor</source>
        <translation>传感器</translation>
    </message>
    <message>
        <source>Batch</source>
        <translation>批号</translation>
    </message>
    <message>
        <source>Points</source>
        <translation>点数</translation>
    </message>
    <message>
        <source>Start (UTC)</source>
        <translation>开始 (UTC)</translation>
    </message>
    <message>
        <source>End (UTC)</source>
        <translation>结束 (UTC)</translation>
    </message>
    <message>
        <source>Start (T+)</source>
        <translation>开始 (T+)</translation>
    </message>
    <message>
        <source>End (T+)</source>
        <translation>结束 (T+)</translation>
    </message>
    <message>
        <source>Duration (min)</source>
        <translation>时长 (分钟)</translation>
    </message>
    <message>
        <source>Length (km)</source>
        <translation>长度 (公里)</translation>
    </message>
    <message>
        <source>Speed (kn)</source>
        <translation>航速 (节)</translation>
    </message>
    <message>
        <source>Maneuvers</source>
        <translation>机动点</translation>
    </message>
    <message>
        <source>Target</source>
        <translation>目标</translation>
    </message>
    <message>
        <source>Status</source>
        <translation>状态</translation>
    </message>
    <message>
        <source>longitude</source>
        <translation>经度</translation>
    </message>
    <message>
        <source>latitude</source>
        <translation>纬度</translation>
    </message>
    <message>
        <source>Error</source>
        <translation>错误</translation>
    </message>
    <message>
        <source>Warning</source>
        <translation>警告</translation>
    </message>
    <message>
        <source>Refused</source>
        <translation>拒绝</translation>
    </message>
    <message>
        <source>Cannot open file</source>
        <translation>无法打开文件</translation>
    </message>
    <message>
        <source>Nothing to run on</source>
        <translation>没有可处理的数据</translation>
    </message>
    <message>
        <source>Open a track file first.</source>
        <translation>请先打开航迹文件。</translation>
    </message>
    <message>
        <source>Running {0}…</source>
        <translation>正在运行 {0}…</translation>
    </message>
    <message>
        <source>{0} done in {1:.1f} s</source>
        <translation>{0} 完成，用时 {1:.1f} 秒</translation>
    </message>
    <message>
        <source>{0} failed</source>
        <translation>{0} 失败</translation>
    </message>
    <message>
        <source>{0} cancelled</source>
        <translation>{0} 已取消</translation>
    </message>
    <message>
        <source>Export</source>
        <translation>导出</translation>
    </message>
    <message>
        <source>Export failed</source>
        <translation>导出失败</translation>
    </message>
    <message>
        <source>exported {0} to {1}</source>
        <translation>已将 {0} 导出到 {1}</translation>
    </message>
    <message>
        <source>this layer has no maneuver points: run Maneuvers or Compress</source>
        <translation>该图层没有机动点：请先运行机动检测或压缩</translation>
    </message>
    <message>
        <source>Autosave failed</source>
        <translation>自动保存失败</translation>
    </message>
    <message>
        <source>Cannot open project</source>
        <translation>无法打开工程</translation>
    </message>
    <message>
        <source>Project not saved</source>
        <translation>工程未保存</translation>
    </message>
    <message>
        <source>Saving the project failed: {0}</source>
        <translation>保存工程失败：{0}</translation>
    </message>
    <message>
        <source>Some changes could not be written to the project file (see the log). Save the work as a new project before closing?</source>
        <translation>部分更改未能写入工程文件（见日志）。关闭前将工作另存为新工程吗？</translation>
    </message>
    <message>
        <source>Note</source>
        <translation>提示</translation>
    </message>
    <message>
        <source>Changes not saved</source>
        <translation>更改未保存</translation>
    </message>
    <message>
        <source>This project was opened read-only, so the changes made since are not in any file. Save them as a new project before closing?</source>
        <translation>此工程以只读方式打开，之后的更改未写入任何文件。关闭前另存为新工程吗？</translation>
    </message>
    <message>
        <source>Project opened with warnings</source>
        <translation>工程已打开（有警告）</translation>
    </message>
    <message>
        <source>Opened project {0}: {1}, {2}</source>
        <translation>已打开工程 {0}：{1}，{2}</translation>
    </message>
    <message>
        <source>1 review row said split or rejected beside a target holding both its tracks (a join made by an older Wakeline): it is now accepted, as a join accepts such rows (stored as a 'repair' decision)</source>
        <translation>1 条审核记录在同时包含其两条航迹的目标旁仍显示“拆分”或“拒绝”（由旧版 Wakeline 的合并造成）：现已改为接受，与当前合并对此类记录的处理一致（记为一条“修复”决策）</translation>
    </message>
    <message>
        <source>{0} review rows said split or rejected beside a target holding both their tracks (joins made by an older Wakeline): they are now accepted, as a join accepts such rows (stored as 'repair' decisions)</source>
        <translation>{0} 条审核记录在同时包含其两条航迹的目标旁仍显示“拆分”或“拒绝”（由旧版 Wakeline 的合并造成）：现已改为接受，与当前合并对此类记录的处理一致（记为“修复”决策）</translation>
    </message>
    <message>
        <source>1 layer</source>
        <translation>1 个图层</translation>
    </message>
    <message>
        <source>{0} layers</source>
        <translation>{0} 个图层</translation>
    </message>
    <message>
        <source>1 review decision restored</source>
        <translation>恢复了 1 条审核决策</translation>
    </message>
    <message>
        <source>{0} review decisions restored</source>
        <translation>恢复了 {0} 条审核决策</translation>
    </message>
    <message>
        <source>(and 1 of an earlier run or a removed layer, kept in the decision log)</source>
        <translation>（另有 1 条属于先前的运行或已移除的图层，保留在决策日志中）</translation>
    </message>
    <message>
        <source>(and {0} of earlier runs or removed layers, kept in the decision log)</source>
        <translation>（另有 {0} 条属于先前的运行或已移除的图层，保留在决策日志中）</translation>
    </message>
    <message>
        <source>Open project</source>
        <translation>打开工程</translation>
    </message>
    <message>
        <source>Save project</source>
        <translation>保存工程</translation>
    </message>
    <message>
        <source>No layer. File ▸ Open tracks… (Ctrl+O)</source>
        <translation>没有图层。文件 ▸ 打开航迹…（Ctrl+O）</translation>
    </message>
    <message>
        <source>Layer</source>
        <translation>图层</translation>
    </message>
    <message>
        <source>Tracks</source>
        <translation>航迹数</translation>
    </message>
    <message>
        <source>Sensors</source>
        <translation>传感器</translation>
    </message>
    <message>
        <source>Time</source>
        <translation>时间</translation>
    </message>
    <message>
        <source>Bearing-only</source>
        <translation>纯方位</translation>
    </message>
    <message>
        <source>{0} cancelled: {1} took its place (one job at a time); run {0} again once it is done</source>
        <translation>{0} 已取消：{1} 取代了它（一次只运行一个任务）；待其完成后请重新运行 {0}</translation>
    </message>
    <message>
        <source>Made by</source>
        <translation>生成方式</translation>
    </message>
    <message>
        <source>Dis_e (mean synchronized distance)</source>
        <translation>Dis_e（平均同步距离）</translation>
    </message>
    <message>
        <source>Maneuver threshold</source>
        <translation>机动阈值</translation>
    </message>
    <message>
        <source>Removed by clean</source>
        <translation>清洗删除</translation>
    </message>
    <message>
        <source>Changed by clean (kept, new values)</source>
        <translation>清洗修改（保留，数值已改）</translation>
    </message>
    <message>
        <source>Replaced by clean</source>
        <translation>清洗替换</translation>
    </message>
    <message>
        <source>Removed or changed by clean</source>
        <translation>清洗删除或修改</translation>
    </message>
    <message>
        <source>[read-only]</source>
        <translation>[只读]</translation>
    </message>
    <message>
        <source>[not saved]</source>
        <translation>[未保存]</translation>
    </message>
    <message>
        <source>&amp;Save pipeline as…</source>
        <translation>流程另存为(&amp;S)…</translation>
    </message>
    <message>
        <source>&amp;Load pipeline…</source>
        <translation>载入流程(&amp;L)…</translation>
    </message>
    <message>
        <source>&amp;Zoom to selection</source>
        <translation>缩放到选中(&amp;Z)</translation>
    </message>
    <message>
        <source>Map &amp;image (PNG)…</source>
        <translation>地图图像(&amp;I)（PNG）…</translation>
    </message>
    <message>
        <source>Active layer &amp;as it came in (layout, encoding, times)…</source>
        <translation>当前图层按原格式导出(&amp;A)（列布局、编码、时间）…</translation>
    </message>
    <message>
        <source>A bearing layer has no tracks: choose a track layer.</source>
        <translation>方位图层没有航迹：请选择航迹图层。</translation>
    </message>
    <message>
        <source>Cannot load pipeline</source>
        <translation>无法载入流程</translation>
    </message>
    <message>
        <source>Pipeline</source>
        <translation>流程</translation>
    </message>
    <message>
        <source>bearing: no observer position, nothing to draw on the map</source>
        <translation>方位：没有观测平台位置，地图上无可绘制的内容</translation>
    </message>
    <message>
        <source>pipeline saved to {0}</source>
        <translation>流程已保存到 {0}</translation>
    </message>
    <message>
        <source>the input layer was removed; result dropped</source>
        <translation>输入图层已被删除；结果已丢弃</translation>
    </message>
    <message>
        <source>A bearing layer has no tracks to export: Export detections… in the Bearing-only dock writes its detections.</source>
        <translation>方位图层没有可导出的航迹：其检测结果请在纯方位面板中用“导出检测结果…”写出。</translation>
    </message>
    <message>
        <source>Export as it came in</source>
        <translation>按原格式导出</translation>
    </message>
    <message>
        <source>the project file is read-only: it opens read-only, changes are not saved</source>
        <translation>工程文件为只读：以只读方式打开，更改不会保存</translation>
    </message>
    <message>
        <source>Export map image</source>
        <translation>导出地图图像</translation>
    </message>
    <message>
        <source>map image written to {0}</source>
        <translation>地图图像已写入 {0}</translation>
    </message>
    <message>
        <source>map image not written: {0}</source>
        <translation>地图图像未写入：{0}</translation>
    </message>
    <message>
        <source>Bearings</source>
        <translation>方位数</translation>
    </message>
    <message>
        <source>Sequences</source>
        <translation>序列数</translation>
    </message>
    <message>
        <source>Detections</source>
        <translation>检测数</translation>
    </message>
    <message>
        <source>Bearing lines</source>
        <translation>方位线长度</translation>
    </message>
    <message>
        <source>Unexpected error</source>
        <translation>意外错误</translation>
    </message>
    <message>
        <source>The details are in the log.</source>
        <translation>详细信息见日志。</translation>
    </message>
    <message>
        <source>export of {0} waits for the export running</source>
        <translation>{0} 的导出等待正在进行的导出完成</translation>
    </message>
    <message>
        <source>the whole layer is written ({0} points): the time window applies to the map, the batch table and the figures, not to exports</source>
        <translation>写出的是整个图层（{0} 个点）：时间窗口只作用于地图、批次表和统计图，不作用于导出</translation>
    </message>
    <message>
        <source>export of {0} cancelled before it started</source>
        <translation>{0} 的导出在开始前已取消</translation>
    </message>
    <message>
        <source>source</source>
        <translation>源数据</translation>
    </message>
    <message>
        <source>cleaned</source>
        <translation>已清洗</translation>
    </message>
    <message>
        <source>maneuvers</source>
        <translation>机动点</translation>
    </message>
    <message>
        <source>compressed</source>
        <translation>已压缩</translation>
    </message>
    <message>
        <source>associated</source>
        <translation>已关联</translation>
    </message>
    <message>
        <source>fused</source>
        <translation>已融合</translation>
    </message>
    <message>
        <source>Made from {0} layers: {1}</source>
        <translation>由 {0} 个图层生成：{1}</translation>
    </message>
    <message>
        <source>bearing</source>
        <translation>方位</translation>
    </message>
    <message>
        <source>{0}: {1}</source>
        <translation>{0}：{1}</translation>
    </message>
    <message>
        <source>{0}:</source>
        <translation>{0}：</translation>
    </message>
    <message>
        <source>{0} m</source>
        <translation>{0} 米</translation>
    </message>
    <message>
        <source>, </source>
        <translation>，</translation>
    </message>
    <message>
        <source>Made at</source>
        <translation>生成时间</translation>
    </message>
</context>
<context>
    <name>ParamsPanel</name>
    <message>
        <source>Parameter</source>
        <translation>参数</translation>
    </message>
    <message>
        <source>Value</source>
        <translation>值</translation>
    </message>
    <message>
        <source>sigma</source>
        <translation>倍标准差</translation>
    </message>
    <message>
        <source>windows</source>
        <translation>个窗口</translation>
    </message>
    <message>
        <source>doublings</source>
        <translation>次加倍</translation>
    </message>
    <message>
        <source>Save preset…</source>
        <translation>保存预设…</translation>
    </message>
    <message>
        <source>Load preset…</source>
        <translation>载入预设…</translation>
    </message>
    <message>
        <source>Defaults</source>
        <translation>恢复默认</translation>
    </message>
    <message>
        <source>Built-in presets</source>
        <translation>内置预设</translation>
    </message>
    <message>
        <source>Measured settings for some kinds of data (options, not defaults): choosing one sets its values and puts the other built-in presets' values still in effect back to their defaults (values you set are kept); the log says what changed</source>
        <translation>针对某类数据实测过的设置（可选项，不是默认值）：选择一个即设置其参数值，并把其他内置预设仍在生效的参数值恢复为默认值（您自己设置的值保留）；日志会列出改动</translation>
    </message>
    <message>
        <source>Built-in preset “{0}” applied: {1}</source>
        <translation>已应用内置预设“{0}”：{1}</translation>
    </message>
    <message>
        <source>Built-in preset “{0}”: every value was already set</source>
        <translation>内置预设“{0}”：所有参数值均已是该设置</translation>
    </message>
    <message>
        <source>Not applied: {0}</source>
        <translation>未应用：{0}</translation>
    </message>
    <message>
        <source>The position noise is large for this sampling (the noise floor of the first windows is {1:.1f} × the threshold on a typical track): the built-in preset “{0}” finds far fewer false turns.</source>
        <translation>相对于此采样，位置噪声较大（典型航迹上，第一级窗口的噪声下限是阈值的 {1:.1f} 倍）：内置预设“{0}”误报的转向少得多。</translation>
    </message>
    <message>
        <source>Save preset</source>
        <translation>保存预设</translation>
    </message>
    <message>
        <source>Load preset</source>
        <translation>载入预设</translation>
    </message>
    <message>
        <source>Cannot load preset</source>
        <translation>无法载入预设</translation>
    </message>
    <message>
        <source>Preset loaded with problems</source>
        <translation>预设已载入（有问题）</translation>
    </message>
    <message>
        <source>Detection limit (seed 000) for this data: median speed {0:.1f} kn, interval {1} s, legs of p = {2} points ({3} s). {4}; with 100 m errors the smallest turn found is {5:.1f}°.</source>
        <translation>本数据的检测极限（种子文献 000）：航速中位数 {0:.1f} 节，采样间隔 {1} 秒，窗口 p = {2} 点（{3} 秒）。{4}；误差为 100 米时，可检出的最小转向为 {5:.1f}°。</translation>
    </message>
    <message>
        <source>A {0:.0f}° turn stands out from position errors up to {1:.0f} m</source>
        <translation>位置误差不超过 {1:.0f} 米时，{0:.0f}° 的转向可被检出</translation>
    </message>
    <message>
        <source>A {0:.0f}° turn stands out only from position errors under 1 m ({1:.2f} m) at this speed and leg</source>
        <translation>在此航速和窗口长度下，只有位置误差小于 1 米（{1:.2f} 米）时，{0:.0f}° 的转向才可被检出</translation>
    </message>
    <message>
        <source>{0} of {1} tracks span {2} h, {3:.0%} of it in long gaps: the speed is taken between the gaps; reading the file with one track per run (a column such as scenario as batch) gives tracks without them.</source>
        <translation>{1} 条航迹中有 {0} 条跨越 {2} 小时，其中 {3:.0%} 为长时间间断：航速按间断之间的航段计算；读取文件时以每次航行为一条航迹（把 scenario 等列映射为批号）可得到没有间断的航迹。</translation>
    </message>
    <message>
        <source>Detection limit (seed 000): none for this data: {0}.</source>
        <translation>本数据无法给出检测极限（种子文献 000）：{0}。</translation>
    </message>
    <message>
        <source>1 row repeats an earlier row of its track (same time and position): not counted here; Clean's duplicates rule removes it.</source>
        <translation>有 1 行与其航迹中较早的一行重复（时间和位置相同）：此处不计入；清洗的重复点规则会将其删除。</translation>
    </message>
    <message>
        <source>{0} rows repeat an earlier row of their track (same time and position): not counted here; Clean's duplicates rule removes them.</source>
        <translation>有 {0} 行与其航迹中较早的一行重复（时间和位置相同）：此处不计入；清洗的重复点规则会将其删除。</translation>
    </message>
    <message>
        <source>resample: max_gap_steps is now 0, so the max_gap_s you set is the gap limit on every track (as with --max-gap). Set max_gap_steps to use the adaptive limit again.</source>
        <translation>重采样：max_gap_steps 已设为 0，您设定的 max_gap_s 即为每条航迹的间断上限（与 --max-gap 相同）。如需再用自适应上限，请设定 max_gap_steps。</translation>
    </message>
    <message>
        <source>Cleaning (seeds 001, 003)</source>
        <translation>清洗（种子文献 001、003）</translation>
    </message>
    <message>
        <source>Cleaning</source>
        <translation>清洗</translation>
    </message>
    <message>
        <source>Maneuvers</source>
        <translation>机动检测</translation>
    </message>
    <message>
        <source>Compression</source>
        <translation>压缩</translation>
    </message>
    <message>
        <source>Association, one sensor</source>
        <translation>关联，单传感器</translation>
    </message>
    <message>
        <source>Association and fusion, several sensors</source>
        <translation>关联与融合，多传感器</translation>
    </message>
    <message>
        <source>Bearing-only</source>
        <translation>纯方位</translation>
    </message>
    <message>
        <source>Smallest turn found for this data: none can be given: {0}.</source>
        <translation>本数据无法给出可检出的最小转向：{0}。</translation>
    </message>
    <message>
        <source>Smallest turn found for this data: {0:.1f}° with 100 m position errors (median speed {1:.1f} kn, interval {2} s). {3}.</source>
        <translation>本数据可检出的最小转向：位置误差为 100 米时为 {0:.1f}°（航速中位数 {1:.1f} 节，采样间隔 {2} 秒）。{3}。</translation>
    </message>
    <message>
        <source>duplicates</source>
        <translation>重复点</translation>
    </message>
    <message>
        <source>stationary</source>
        <translation>静止点</translation>
    </message>
    <message>
        <source>speed</source>
        <translation>速度跳变</translation>
    </message>
    <message>
        <source>turn</source>
        <translation>转向异常</translation>
    </message>
    <message>
        <source>speed outliers</source>
        <translation>速度离群点</translation>
    </message>
    <message>
        <source>isolated</source>
        <translation>孤立点</translation>
    </message>
    <message>
        <source>short tracks</source>
        <translation>短航迹</translation>
    </message>
    <message>
        <source>bspline</source>
        <translation>B 样条</translation>
    </message>
    <message>
        <source>resample</source>
        <translation>重采样</translation>
    </message>
    <message>
        <source>smooth</source>
        <translation>平滑</translation>
    </message>
    <message>
        <source>Maneuvers (seed 000)</source>
        <translation>机动检测（种子文献 000）</translation>
    </message>
    <message>
        <source>Compression (seed 000)</source>
        <translation>压缩（种子文献 000）</translation>
    </message>
    <message>
        <source>Association, one sensor (seeds 001, 003)</source>
        <translation>关联，单传感器（种子文献 001、003）</translation>
    </message>
    <message>
        <source>Association and fusion, several sensors (seed 003)</source>
        <translation>关联与融合，多传感器（种子文献 003）</translation>
    </message>
    <message>
        <source>Bearing-only (seed 002)</source>
        <translation>纯方位（种子文献 002）</translation>
    </message>
    <message>
        <source>Maneuver detector</source>
        <translation>机动检测方法</translation>
    </message>
    <message>
        <source>Compression method</source>
        <translation>压缩方法</translation>
    </message>
    <message>
        <source>Association mode</source>
        <translation>关联模式</translation>
    </message>
    <message>
        <source>Fusion distance and assignment</source>
        <translation>融合距离与分配</translation>
    </message>
    <message>
        <source>points</source>
        <translation>点</translation>
    </message>
    <message>
        <source>samples</source>
        <translation>个样本</translation>
    </message>
    <message>
        <source>fixes</source>
        <translation>个定位点</translation>
    </message>
    <message>
        <source>intervals</source>
        <translation>个间隔</translation>
    </message>
    <message>
        <source>steps</source>
        <translation>步</translation>
    </message>
    <message>
        <source>at-rest windows</source>
        <translation>个静止窗口</translation>
    </message>
    <message>
        <source>deg</source>
        <translation>度</translation>
    </message>
    <message>
        <source>s</source>
        <translation>秒</translation>
    </message>
    <message>
        <source>m</source>
        <translation>米</translation>
    </message>
    <message>
        <source>km</source>
        <translation>公里</translation>
    </message>
    <message>
        <source>kn</source>
        <translation>节</translation>
    </message>
    <message>
        <source>m/s</source>
        <translation>米/秒</translation>
    </message>
    <message>
        <source>m/s²</source>
        <translation>米/秒²</translation>
    </message>
</context>
<context>
    <name>DetailPanel</name>
    <message>
        <source>Bearing over time</source>
        <translation>方位随时间</translation>
    </message>
    <message>
        <source>The bearing sequence and the detector's z statistic</source>
        <translation>方位序列及检测器的 z 统计量</translation>
    </message>
    <message>
        <source>Compression</source>
        <translation>压缩</translation>
    </message>
    <message>
        <source>Maneuver factor</source>
        <translation>机动因子</translation>
    </message>
    <message>
        <source>Compressed over original</source>
        <translation>压缩与原始对比</translation>
    </message>
    <message>
        <source>{0} maneuvers; threshold {1:g}°</source>
        <translation>{0} 个机动点；阈值 {1:g}°</translation>
    </message>
    <message>
        <source>1 maneuver; threshold {1:g}°</source>
        <translation>1 个机动点；阈值 {1:g}°</translation>
    </message>
    <message>
        <source>No track selected.&lt;br&gt;Click one on the map or in the table.</source>
        <translation>未选择航迹。&lt;br&gt;请在地图或表中点选一条。</translation>
    </message>
    <message>
        <source>No track selected</source>
        <translation>未选择航迹</translation>
    </message>
    <message>
        <source>No δ for a fused track: run Maneuvers on its layer</source>
        <translation>融合航迹没有 δ：请对其图层运行机动检测</translation>
    </message>
    <message>
        <source>No δ for this track: run Maneuvers on its layer</source>
        <translation>此航迹没有 δ：请对其图层运行机动检测</translation>
    </message>
    <message>
        <source>{0} of {1} points kept, Dis_e {2:.0f} m</source>
        <translation>保留 {0}/{1} 点，Dis_e {2:.0f} 米</translation>
    </message>
    <message>
        <source>run Compress to compare</source>
        <translation>运行压缩以对比</translation>
    </message>
    <message>
        <source>Bearing-only</source>
        <translation>纯方位</translation>
    </message>
    <message>
        <source>{0}: {1} maneuvers detected; band ±{2:.2f}</source>
        <translation>{0}：检测到 {1} 次机动；阈值带 ±{2:.2f}</translation>
    </message>
    <message>
        <source>{0}: 1 maneuver detected; band ±{2:.2f}</source>
        <translation>{0}：检测到 {1} 次机动；阈值带 ±{2:.2f}</translation>
    </message>
    <message>
        <source>min</source>
        <translation>分钟</translation>
    </message>
    <message>
        <source>time since track start</source>
        <translation>航迹开始后的时间</translation>
    </message>
    <message>
        <source>maneuver factor δ</source>
        <translation>机动因子 δ</translation>
    </message>
    <message>
        <source>longitude</source>
        <translation>经度</translation>
    </message>
    <message>
        <source>latitude</source>
        <translation>纬度</translation>
    </message>
    <message>
        <source>bearing</source>
        <translation>方位</translation>
    </message>
    <message>
        <source>time</source>
        <translation>时间</translation>
    </message>
    <message>
        <source>z (GLR)</source>
        <translation>z（GLR）</translation>
    </message>
    <message>
        <source>z (AUC)</source>
        <translation>z（AUC）</translation>
    </message>
</context>
<context>
    <name>ImportReportDialog</name>
    <message>
        <source>Import report: {0}</source>
        <translation>导入报告：{0}</translation>
    </message>
    <message>
        <source>Quarantined rows ({0:,}; the first {1:,} are kept):</source>
        <translation>隔离行（{0:,} 行；保留前 {1:,} 行）：</translation>
    </message>
    <message>
        <source>line</source>
        <translation>行号</translation>
    </message>
    <message>
        <source>reason</source>
        <translation>原因</translation>
    </message>
    <message>
        <source>text</source>
        <translation>原文</translation>
    </message>
</context>
<context>
    <name>ImportDialog</name>
    <message>
        <source>Reading the first {0} rows:</source>
        <translation>读取前 {0} 行：</translation>
    </message>
    <message>
        <source>{0} of the first {1} rows would be quarantined: {2}</source>
        <translation>前 {1} 行中有 {0} 行将被隔离：{2}</translation>
    </message>
    <message>
        <source>Nothing would be imported: {0}</source>
        <translation>将不会导入任何内容：{0}</translation>
    </message>
    <message>
        <source>Map a column to each required field first: {0}</source>
        <translation>请先为每个必填字段指定列：{0}</translation>
    </message>
    <message>
        <source>Lines above the header</source>
        <translation>表头上方的行数</translation>
    </message>
    <message>
        <source>The file has no header: its columns were chosen by their values. Check them against the first rows.</source>
        <translation>文件没有表头：各列是按其数值选定的。请对照前几行检查。</translation>
    </message>
    <message>
        <source>Which degree column is longitude ({0} or {1}) does not show in the values: swap them if the tracks lie in the wrong place.</source>
        <translation>数值看不出哪一列度数是经度（{0} 或 {1}）：如果航迹位置不对，请交换这两列。</translation>
    </message>
    <message>
        <source>Origin of x/y metres</source>
        <translation>x/y 米制坐标的原点</translation>
    </message>
    <message>
        <source>LAT, LON (only for x/y metres)</source>
        <translation>纬度, 经度（仅用于 x/y 米制坐标）</translation>
    </message>
    <message>
        <source>Latitude and longitude (degrees) of the point a file's x/y or east/north metres are measured from: the radar's site or the frame's zero.</source>
        <translation>文件中 x/y 或东/北向米制坐标所依据的原点的纬度和经度（度）：雷达站址或坐标系零点。</translation>
    </message>
    <message>
        <source>Date order</source>
        <translation>日期顺序</translation>
    </message>
    <message>
        <source>day first (dd/mm/yyyy)</source>
        <translation>日在前（日/月/年）</translation>
    </message>
    <message>
        <source>month first (mm/dd/yyyy)</source>
        <translation>月在前（月/日/年）</translation>
    </message>
    <message>
        <source>Time numbers</source>
        <translation>时间数值</translation>
    </message>
    <message>
        <source>auto (knots)</source>
        <translation>自动（节）</translation>
    </message>
    <message>
        <source>knots</source>
        <translation>节</translation>
    </message>
    <message>
        <source>m/s</source>
        <translation>米/秒</translation>
    </message>
    <message>
        <source>km/h</source>
        <translation>公里/小时</translation>
    </message>
    <message>
        <source>mph</source>
        <translation>英里/小时</translation>
    </message>
    <message>
        <source>Unit of a speed column whose header names none; a header such as speed_mps, sog_kmh or Speed (m/s) names its own. Speeds are converted to knots.</source>
        <translation>表头未注明单位的航速列的单位；speed_mps、sog_kmh 或 Speed (m/s) 这样的表头自带单位。航速换算为节。</translation>
    </message>
    <message>
        <source>auto (metres)</source>
        <translation>自动（米）</translation>
    </message>
    <message>
        <source>metres</source>
        <translation>米</translation>
    </message>
    <message>
        <source>km</source>
        <translation>公里</translation>
    </message>
    <message>
        <source>nautical miles</source>
        <translation>海里</translation>
    </message>
    <message>
        <source>yards</source>
        <translation>码</translation>
    </message>
    <message>
        <source>Unit of x/y, offsets and range on a local plane whose headers name none; a header such as x_km, range_nm or y_yd names its own.</source>
        <translation>表头未注明单位的局部平面 x/y、偏移量和距离的单位；x_km、range_nm 或 y_yd 这样的表头自带单位。</translation>
    </message>
    <message>
        <source>Speed unit</source>
        <translation>航速单位</translation>
    </message>
    <message>
        <source>Distance unit</source>
        <translation>距离单位</translation>
    </message>
    <message>
        <source>seconds</source>
        <translation>秒</translation>
    </message>
    <message>
        <source>Excel serial days</source>
        <translation>Excel 序列日数</translation>
    </message>
    <message>
        <source>Numbers in the time column: seconds (unix, or from a scene start) or Excel serial days (45658.5 is 2025-01-01 12:00). Auto takes Excel days when all lie between 20000 and 80000 and the header says so or they step less than 0.01 between rows; the import says which it read.</source>
        <translation>时间列中的数值：秒（Unix 时间，或自场景开始起算）或 Excel 序列日数（45658.5 即 2025-01-01 12:00）。“自动”在所有数值均介于 20000 与 80000 之间、且表头注明或相邻行间步长小于 0.01 时按 Excel 日数读取；导入报告会说明按哪种读取。</translation>
    </message>
    <message>
        <source>How dates like 03/04/2025 read: auto reads them day first unless a date shows the month first (a second number above 12); the import says what decided it.</source>
        <translation>如何读取 03/04/2025 这类日期：“自动”按日在前读取，除非某个日期表明月在前（第二个数大于 12）；导入报告会说明依据。</translation>
    </message>
    <message>
        <source>YYYY-MM-DD (only for times without a date)</source>
        <translation>YYYY-MM-DD（仅用于不带日期的时间）</translation>
    </message>
    <message>
        <source>The day of times written without a date (23:50:00.5): they are read on it, a day later after each step back past midnight within a track. Empty: 1970-01-01, as relative times.</source>
        <translation>不带日期的时间（如 23:50:00.5）所在的日期：按此日期读取，同一航迹内时间每回退越过午夜一次即记为次日。留空：按 1970-01-01 读取为相对时间。</translation>
    </message>
    <message>
        <source>Date of clock times</source>
        <translation>时刻的日期</translation>
    </message>
    <message>
        <source>Date of clock times {0}: give it as YYYY-MM-DD.</source>
        <translation>时刻的日期 {0}：请按 YYYY-MM-DD 填写。</translation>
    </message>
    <message>
        <source>The times in {0} are times of day without a date: give their Date of clock times, or they are read on 1970-01-01 as relative times.</source>
        <translation>{0} 中的时间是不带日期的时刻：请填写“时刻的日期”，否则按 1970-01-01 读取为相对时间。</translation>
    </message>
    <message>
        <source>Lines before the header (a title or notes), skipped and counted; auto finds a title of up to 10 lines above a header naming known columns.</source>
        <translation>表头之前的行（标题或说明），跳过并计数；“自动”可识别表头（含已知列名）上方最多 10 行的标题。</translation>
    </message>
    <message>
        <source>auto</source>
        <translation>自动</translation>
    </message>
    <message>
        <source>{0} line(s) above the header skipped</source>
        <translation>已跳过表头上方的 {0} 行</translation>
    </message>
    <message>
        <source>Import tracks</source>
        <translation>导入航迹</translation>
    </message>
    <message>
        <source>Browse…</source>
        <translation>浏览…</translation>
    </message>
    <message>
        <source>sensor name when the file has none</source>
        <translation>文件中没有传感器时使用的名称</translation>
    </message>
    <message>
        <source>File</source>
        <translation>文件</translation>
    </message>
    <message>
        <source>Layout</source>
        <translation>格式</translation>
    </message>
    <message>
        <source>Encoding</source>
        <translation>编码</translation>
    </message>
    <message>
        <source>Column mapping</source>
        <translation>列映射</translation>
    </message>
    <message>
        <source>Sensor</source>
        <translation>传感器</translation>
    </message>
    <message>
        <source>First rows of the file:</source>
        <translation>文件前几行：</translation>
    </message>
    <message>
        <source>Open track file</source>
        <translation>打开航迹文件</translation>
    </message>
    <message>
        <source>Time zone</source>
        <translation>时区</translation>
    </message>
    <message>
        <source>Zone of times written without one (IANA name or ±HH:MM). Unix times are absolute and not shifted.</source>
        <translation>未注明时区的时间所用的时区（IANA 名称或 ±HH:MM）。Unix 时间是绝对时间，不作偏移。</translation>
    </message>
    <message>
        <source>Detected</source>
        <translation>识别结果</translation>
    </message>
    <message>
        <source>no layout fits</source>
        <translation>没有匹配的格式</translation>
    </message>
    <message>
        <source>delimiter</source>
        <translation>分隔符</translation>
    </message>
    <message>
        <source>Unmapped columns (kept as extra columns): {0}</source>
        <translation>未映射的列（作为附加列保留）：{0}</translation>
    </message>
    <message>
        <source>The time column {0} holds local times: choose their time zone, or they are read as UTC.</source>
        <translation>时间列 {0} 是本地时间：请选择其时区，否则按 UTC 读取。</translation>
    </message>
    <message>
        <source>Choose the time column.</source>
        <translation>请选择时间列。</translation>
    </message>
    <message>
        <source>Required fields still without a column: {0}.</source>
        <translation>尚未指定列的必填字段：{0}。</translation>
    </message>
</context>
<context>
    <name>BearingView</name>
    <message>
        <source>batch</source>
        <translation>批号</translation>
    </message>
    <message>
        <source>detect_time</source>
        <translation>检测时间</translation>
    </message>
    <message>
        <source>maneuver_time</source>
        <translation>机动时间</translation>
    </message>
    <message>
        <source>Export detections…</source>
        <translation>导出检测结果…</translation>
    </message>
    <message>
        <source>Line length</source>
        <translation>方位线长度</translation>
    </message>
    <message>
        <source>from the data</source>
        <translation>由数据决定</translation>
    </message>
    <message>
        <source>Length of the bearing lines from the observer; lowest value: from the data (past the targets' ranges when known, else the scene's scale)</source>
        <translation>方位线从观测平台起算的长度；最小值：由数据决定（已知目标距离时画过目标距离，否则按场景尺度）</translation>
    </message>
    <message>
        <source>longitude</source>
        <translation>经度</translation>
    </message>
    <message>
        <source>latitude</source>
        <translation>纬度</translation>
    </message>
    <message>
        <source>No observer position: no bearing lines to draw.</source>
        <translation>没有观测平台位置：无法绘制方位线。</translation>
    </message>
    <message>
        <source>Export detections</source>
        <translation>导出检测结果</translation>
    </message>
    <message>
        <source>Cannot export</source>
        <translation>无法导出</translation>
    </message>
    <message>
        <source>observer</source>
        <translation>观测平台</translation>
    </message>
    <message>
        <source>bearing lines</source>
        <translation>方位线</translation>
    </message>
    <message>
        <source>maneuvers</source>
        <translation>机动点</translation>
    </message>
    <message>
        <source>other batches</source>
        <translation>其他批次</translation>
    </message>
    <message>
        <source>m</source>
        <translation>米</translation>
    </message>
</context>
<context>
    <name>TimePanel</name>
    <message>
        <source>Time window: none (every time shown)</source>
        <translation>时间窗：无（显示全部时间）</translation>
    </message>
    <message>
        <source>Time window: {0}</source>
        <translation>时间窗：{0}</translation>
    </message>
    <message>
        <source>From here</source>
        <translation>从此处开始</translation>
    </message>
    <message>
        <source>Play / pause</source>
        <translation>播放 / 暂停</translation>
    </message>
    <message>
        <source>Positions</source>
        <translation>显示位置</translation>
    </message>
    <message>
        <source>Scene seconds per second of playback</source>
        <translation>回放时每秒对应的场景秒数</translation>
    </message>
    <message>
        <source>Show each track's position at the slider's time</source>
        <translation>显示各航迹在滑块时刻的位置</translation>
    </message>
    <message>
        <source>Show only points inside [from, to] on the map, and tracks overlapping it in the table</source>
        <translation>地图只显示 [起, 止] 时间窗内的点，批次表只列出与其重叠的航迹</translation>
    </message>
    <message>
        <source>Speed</source>
        <translation>速度</translation>
    </message>
    <message>
        <source>Step</source>
        <translation>步长</translation>
    </message>
    <message>
        <source>Step back</source>
        <translation>后退一步</translation>
    </message>
    <message>
        <source>Step forward</source>
        <translation>前进一步</translation>
    </message>
    <message>
        <source>The window ends at the slider's time</source>
        <translation>时间窗在滑块时刻结束</translation>
    </message>
    <message>
        <source>The window starts at the slider's time</source>
        <translation>时间窗从滑块时刻开始</translation>
    </message>
    <message>
        <source>Time moved by one step</source>
        <translation>每步移动的时间</translation>
    </message>
    <message>
        <source>Time window</source>
        <translation>时间窗</translation>
    </message>
    <message>
        <source>Time: every visible track is shown at its position then</source>
        <translation>时间：每条可见航迹显示其在该时刻的位置</translation>
    </message>
    <message>
        <source>To here</source>
        <translation>到此处结束</translation>
    </message>
    <message>
        <source>Trail</source>
        <translation>尾迹</translation>
    </message>
    <message>
        <source>Trail drawn behind each position (0: markers only)</source>
        <translation>每个位置后绘制的尾迹长度（0：只显示标记）</translation>
    </message>
    <message>
        <source>min</source>
        <translation>分钟</translation>
    </message>
    <message>
        <source>s</source>
        <translation>秒</translation>
    </message>
    <message>
        <source>{0} to {1}</source>
        <translation>{0} 至 {1}</translation>
    </message>
</context>
<context>
    <name>ReviewPanel</name>
    <message>
        <source>optimal</source>
        <translation>最优分配</translation>
    </message>
    <message>
        <source>greedy</source>
        <translation>贪心分配</translation>
    </message>
    <message>
        <source>motion</source>
        <translation>运动</translation>
    </message>
    <message>
        <source>area</source>
        <translation>面积</translation>
    </message>
    <message>
        <source>hausdorff</source>
        <translation>豪斯多夫</translation>
    </message>
    <message>
        <source>DTW, whole tracks</source>
        <translation>DTW（整条航迹）</translation>
    </message>
    <message>
        <source>sync</source>
        <translation>同步</translation>
    </message>
    <message>
        <source>second look (gap beyond T_gap)</source>
        <translation>第二次查看（间隙超过 T_gap）</translation>
    </message>
    <message>
        <source>(scaled)</source>
        <translation>（归一化）</translation>
    </message>
    <message>
        <source>&lt;b&gt;{0}&lt;/b&gt; ({1}) {2} → {3}, {4}: cost {5} {6} (gate {7})</source>
        <translation>&lt;b&gt;{0}&lt;/b&gt;（{1}）{2} → {3}，{4}：代价 {5} {6}（门限 {7}）</translation>
    </message>
    <message>
        <source>Accept</source>
        <translation>接受</translation>
    </message>
    <message>
        <source>Merge</source>
        <translation>合并</translation>
    </message>
    <message>
        <source>Next proposal</source>
        <translation>下一条建议</translation>
    </message>
    <message>
        <source>Previous proposal</source>
        <translation>上一条建议</translation>
    </message>
    <message>
        <source>Redo</source>
        <translation>重做</translation>
    </message>
    <message>
        <source>Reject</source>
        <translation>拒绝</translation>
    </message>
    <message>
        <source>Split target</source>
        <translation>拆分目标</translation>
    </message>
    <message>
        <source>Split track</source>
        <translation>拆出航迹</translation>
    </message>
    <message>
        <source>Undo</source>
        <translation>撤销</translation>
    </message>
    <message>
        <source>accept: the two tracks are one ship</source>
        <translation>接受：两条航迹属于同一艘船</translation>
    </message>
    <message>
        <source>accepted</source>
        <translation>已接受</translation>
    </message>
    <message>
        <source>all</source>
        <translation>全部</translation>
    </message>
    <message>
        <source>all sensors</source>
        <translation>全部传感器</translation>
    </message>
    <message>
        <source>cost</source>
        <translation>代价</translation>
    </message>
    <message>
        <source>distance m</source>
        <translation>距离 (米)</translation>
    </message>
    <message>
        <source>distance {0:.0f} m</source>
        <translation>距离 {0:.0f} 米</translation>
    </message>
    <message>
        <source>gap s</source>
        <translation>间隔 (秒)</translation>
    </message>
    <message>
        <source>gap {0:.0f} s</source>
        <translation>间隔 {0:.0f} 秒</translation>
    </message>
    <message>
        <source>highest cost first</source>
        <translation>代价最高优先</translation>
    </message>
    <message>
        <source>id</source>
        <translation>编号</translation>
    </message>
    <message>
        <source>least margin first</source>
        <translation>裕度最小优先</translation>
    </message>
    <message>
        <source>m</source>
        <translation>米</translation>
    </message>
    <message>
        <source>margin</source>
        <translation>裕度</translation>
    </message>
    <message>
        <source>margin {0}. Target {1}: {2}</source>
        <translation>裕度 {0}。目标 {1}：{2}</translation>
    </message>
    <message>
        <source>merge the tracks of the selected rows</source>
        <translation>合并所选行的航迹</translation>
    </message>
    <message>
        <source>method</source>
        <translation>方法</translation>
    </message>
    <message>
        <source>next proposal in the queue</source>
        <translation>队列中的下一条建议</translation>
    </message>
    <message>
        <source>no runner-up (the alternative is leaving both unmatched)</source>
        <translation>无次优候选（另一选择是两者都不关联）</translation>
    </message>
    <message>
        <source>overlap {0:.0f} s</source>
        <translation>重叠 {0:.0f} 秒</translation>
    </message>
    <message>
        <source>&lt;b&gt;plots, not tracks&lt;/b&gt;: {0} (several positions at one time: several targets and clutter), so the distance and margin say little</source>
        <translation>&lt;b&gt;是点迹而非航迹&lt;/b&gt;：{0}（同一时刻有多个位置：多个目标和杂波），因此距离和裕度意义不大</translation>
    </message>
    <message>
        <source>pending</source>
        <translation>待审</translation>
    </message>
    <message>
        <source>position misfit {0:.0f} m</source>
        <translation>位置偏差 {0:.0f} 米</translation>
    </message>
    <message>
        <source>previous proposal</source>
        <translation>上一条建议</translation>
    </message>
    <message>
        <source>proposal</source>
        <translation>建议</translation>
    </message>
    <message>
        <source>reject: not one ship; never proposed again</source>
        <translation>拒绝：不是同一艘船；不再提出</translation>
    </message>
    <message>
        <source>rejected</source>
        <translation>已拒绝</translation>
    </message>
    <message>
        <source>runner-up</source>
        <translation>次优候选</translation>
    </message>
    <message>
        <source>runner-up (or the gate) cost minus this cost: small = uncertain</source>
        <translation>次优候选（或门限）代价减去本代价：越小越不确定</translation>
    </message>
    <message>
        <source>runner-up {0} at {1}</source>
        <translation>次优候选 {0}，代价 {1}</translation>
    </message>
    <message>
        <source>split</source>
        <translation>已拆分</translation>
    </message>
    <message>
        <source>status</source>
        <translation>状态</translation>
    </message>
    <message>
        <source>the target falls back into its tracks</source>
        <translation>目标拆回各条航迹</translation>
    </message>
    <message>
        <source>track A</source>
        <translation>航迹 A</translation>
    </message>
    <message>
        <source>track B</source>
        <translation>航迹 B</translation>
    </message>
    <message>
        <source>track B leaves its target</source>
        <translation>航迹 B 离开其目标</translation>
    </message>
    <message>
        <source>{0} proposals: {1} pending, {2} accepted, {3} rejected, {4} split</source>
        <translation>{0} 条建议：{1} 待审，{2} 已接受，{3} 已拒绝，{4} 已拆分</translation>
    </message>
    <message>
        <source>Δcourse {0:.1f}°</source>
        <translation>航向差 {0:.1f}°</translation>
    </message>
    <message>
        <source>Δspeed {0:.1f} kn</source>
        <translation>航速差 {0:.1f} 节</translation>
    </message>
    <message>
        <source>spread of the prediction +{0:.2f}</source>
        <translation>预测离散 +{0:.2f}</translation>
    </message>
    <message>
        <source>an end turns or changes speed ({0:.2g} m/s²): wider gate</source>
        <translation>航迹端点在转向或变速（{0:.2g} 米/秒²）：门限放宽</translation>
    </message>
    <message>
        <source>; </source>
        <translation>；</translation>
    </message>
</context>
<context>
    <name>ReviewCommand</name>
    <message>
        <source>accept</source>
        <translation>接受</translation>
    </message>
    <message>
        <source>merge</source>
        <translation>合并</translation>
    </message>
    <message>
        <source>reject</source>
        <translation>拒绝</translation>
    </message>
    <message>
        <source>reset</source>
        <translation>重置</translation>
    </message>
    <message>
        <source>split target</source>
        <translation>拆分目标</translation>
    </message>
    <message>
        <source>repair</source>
        <translation>修复</translation>
    </message>
    <message>
        <source>split track</source>
        <translation>拆出航迹</translation>
    </message>
    <message>
        <source>{0} {1}</source>
        <translation>{0} {1}</translation>
    </message>
</context>
<context>
    <name>GanttView</name>
    <message>
        <source>min</source>
        <translation>分钟</translation>
    </message>
    <message>
        <source>time</source>
        <translation>时间</translation>
    </message>
</context>
<context>
    <name>ReviewWorkspace</name>
    <message>
        <source>latitude</source>
        <translation>纬度</translation>
    </message>
    <message>
        <source>longitude</source>
        <translation>经度</translation>
    </message>
</context>
<context>
    <name>ReviewDock</name>
    <message>
        <source>Review: 0 proposals on {0}; nothing to review (Review ▸ Review opens the queue)</source>
        <translation>审核：{0} 上有 0 个提议，无需审核（审核 ▸ 审核 可打开队列）</translation>
    </message>
    <message>
        <source>undo {0}</source>
        <translation>撤销{0}</translation>
    </message>
    <message>
        <source>redo {0}</source>
        <translation>重做{0}</translation>
    </message>
    <message>
        <source>Review: {0} {1}</source>
        <translation>审核：{0} {1}</translation>
    </message>
    <message>
        <source>&amp;Undo (nothing since the repair made on opening)</source>
        <translation>撤销(&amp;U)（打开时修复以来没有可撤销的）</translation>
    </message>
    <message>
        <source>Opening the project repaired decisions an older Wakeline left inconsistent; decisions made before the repair are changed by deciding again (Accept, Reject, Reset), and the decision log keeps every one.</source>
        <translation>打开工程时修复了旧版 Wakeline 留下的不一致决策；修复之前的决策可通过重新决策（接受、拒绝、重置）来更改，决策日志保留每一条。</translation>
    </message>
    <message>
        <source>&amp;Next proposal</source>
        <translation>下一条建议(&amp;N)</translation>
    </message>
    <message>
        <source>&amp;Previous proposal</source>
        <translation>上一条建议(&amp;P)</translation>
    </message>
    <message>
        <source>&amp;Accept</source>
        <translation>接受(&amp;A)</translation>
    </message>
    <message>
        <source>&amp;Reject</source>
        <translation>拒绝(&amp;R)</translation>
    </message>
    <message>
        <source>&amp;Split track</source>
        <translation>拆出航迹(&amp;S)</translation>
    </message>
    <message>
        <source>Split &amp;target</source>
        <translation>拆分目标(&amp;T)</translation>
    </message>
    <message>
        <source>&amp;Merge selected rows</source>
        <translation>合并所选行(&amp;M)</translation>
    </message>
    <message>
        <source>Before/after &amp;map (linked)</source>
        <translation>前后对照地图（联动）(&amp;M)</translation>
    </message>
    <message>
        <source>&amp;Decision log…</source>
        <translation>决策日志(&amp;D)…</translation>
    </message>
    <message>
        <source>&amp;Edit</source>
        <translation>编辑(&amp;E)</translation>
    </message>
    <message>
        <source>&amp;Redo</source>
        <translation>重做(&amp;R)</translation>
    </message>
    <message>
        <source>&amp;Reviewed tracks (decisions honoured)…</source>
        <translation>审核后的航迹（按决策）(&amp;R)…</translation>
    </message>
    <message>
        <source>&amp;Undo</source>
        <translation>撤销(&amp;U)</translation>
    </message>
    <message>
        <source>&amp;Undo (nothing since the step ran again)</source>
        <translation>撤销(&amp;U)（重新运行步骤后尚无可撤销的操作）</translation>
    </message>
    <message>
        <source>Running a step again is not undone by Undo (no layer edit is): the decisions of the earlier run that still apply, those made while it ran included, were carried over, and the decision log keeps every one.</source>
        <translation>重新运行步骤不能用“撤销”撤回（图层编辑都不能撤销）：先前运行中仍然适用的决策（包括运行期间做出的决策）已沿用，决策日志保留全部决策。</translation>
    </message>
    <message>
        <source>Error</source>
        <translation>错误</translation>
    </message>
    <message>
        <source>Fuse selected la&amp;yers (two or more)</source>
        <translation>融合所选图层（两个或以上）(&amp;Y)</translation>
    </message>
    <message>
        <source>No proposals: run Associate or Fuse on a layer.</source>
        <translation>没有候选：请对图层运行关联或融合。</translation>
    </message>
    <message>
        <source>Revie&amp;w</source>
        <translation>审核(&amp;W)</translation>
    </message>
    <message>
        <source>Review</source>
        <translation>审核</translation>
    </message>
    <message>
        <source>before: the input pieces</source>
        <translation>之前：输入的航迹段</translation>
    </message>
    <message>
        <source>members</source>
        <translation>成员</translation>
    </message>
    <message>
        <source>points by sensors</source>
        <translation>各传感器点数</translation>
    </message>
</context>
<context>
    <name>ReviewSync</name>
    <message>
        <source>{0} points of {1} (reviewed tracks)</source>
        <translation>{1} 的 {0} 个点（审核后的航迹）</translation>
    </message>
    <message>
        <source>{0} points of {1} (reviewed tracks, from the {2} layer)</source>
        <translation>{1} 的 {0} 个点（审核后的航迹，由{2}图层生成）</translation>
    </message>
    <message>
        <source>: the {0} layer holds {1} points</source>
        <translation>；{0}图层有 {1} 个点</translation>
    </message>
    <message>
        <source>{0} of {1} proposals not reviewed: counted as accepted</source>
        <translation>{1} 个提议中有 {0} 个未审核：按接受计</translation>
    </message>
    <message>
        <source>{0}: decision log</source>
        <translation>{0}：决策日志</translation>
    </message>
    <message>
        <source>{0} (reviewed tracks)</source>
        <translation>{0}（审核后的航迹）</translation>
    </message>
    <message>
        <source>{0}: {1} → {2}</source>
        <translation>{0}：{1} → {2}</translation>
    </message>
    <message>
        <source>Sensors of one name in several files fuse as the files&apos; names: {0}</source>
        <translation>多个文件中同名的传感器按文件名区分后融合：{0}</translation>
    </message>
    <message>
        <source>Fuse</source>
        <translation>多源融合</translation>
    </message>
    <message>
        <source>Fuse needs tracks of two sensors or more: {0} holds only {1}.</source>
        <translation>多源融合需要至少两个传感器的航迹：{0} 只有 {1}。</translation>
    </message>
    <message>
        <source>To fuse files (e.g. radar and AIS), select two or more layers in the Layers list (Ctrl+click) and choose Run ▸ Fuse selected layers.</source>
        <translation>要融合多个文件（如雷达和 AIS），请在图层列表中选择两个或以上图层（Ctrl+单击），再选择 运行 ▸ 融合所选图层。</translation>
    </message>
    <message>
        <source>Fuse it with {0}?</source>
        <translation>与 {0} 融合吗？</translation>
    </message>
    <message>
        <source>Fuse it with:</source>
        <translation>与以下图层融合：</translation>
    </message>
    <message>
        <source>{0} on {1}</source>
        <translation>对 {1} 运行{0}</translation>
    </message>
    <message>
        <source>Error</source>
        <translation>错误</translation>
    </message>
    <message>
        <source>Export decision log</source>
        <translation>导出决策日志</translation>
    </message>
    <message>
        <source>Export reviewed tracks</source>
        <translation>导出审核后的航迹</translation>
    </message>
    <message>
        <source>Fuse selected layers</source>
        <translation>融合所选图层</translation>
    </message>
    <message>
        <source>No layer under review.</source>
        <translation>没有正在审核的图层。</translation>
    </message>
    <message>
        <source>Nothing to export</source>
        <translation>没有可导出的内容</translation>
    </message>
    <message>
        <source>Select two or more layers in the Layers list (Ctrl+click), e.g. radar and AIS.</source>
        <translation>在图层列表中选择两个或更多图层（Ctrl+单击），例如雷达和 AIS。</translation>
    </message>
    <message>
        <source>{0} and {1} both come from {2}: fusing them would count its points twice. Select one of them (Ctrl+click to unselect).</source>
        <translation>{0} 和 {1} 都来自 {2}：融合它们会把其中的点计算两次。请只选择其中一个（Ctrl+单击可取消选择）。</translation>
    </message>
    <message>
        <source>an input layer was removed; result dropped</source>
        <translation>一个输入图层已被删除；结果已丢弃</translation>
    </message>
</context>
<context>
    <name>StatsPanel</name>
    <message>
        <source>Points in the window</source>
        <translation>时间窗内的点数</translation>
    </message>
    <message>
        <source>Tracks with points in the window</source>
        <translation>在时间窗内有点的航迹数</translation>
    </message>
    <message>
        <source>Points</source>
        <translation>点数</translation>
    </message>
    <message>
        <source>Tracks</source>
        <translation>航迹数</translation>
    </message>
    <message>
        <source>Sensor {0}</source>
        <translation>传感器 {0}</translation>
    </message>
    <message>
        <source>{0}, {1}, median interval {2}</source>
        <translation>{0}，{1}，采样间隔中位数 {2}</translation>
    </message>
    <message>
        <source>1 track</source>
        <translation>1 条航迹</translation>
    </message>
    <message>
        <source>{0} tracks</source>
        <translation>{0} 条航迹</translation>
    </message>
    <message>
        <source>1 point</source>
        <translation>1 个点</translation>
    </message>
    <message>
        <source>{0} points</source>
        <translation>{0} 个点</translation>
    </message>
    <message>
        <source>Targets</source>
        <translation>目标数</translation>
    </message>
    <message>
        <source>no target ids</source>
        <translation>无目标编号</translation>
    </message>
    <message>
        <source>Track lifetime min / median / 90 % / max</source>
        <translation>航迹持续时间 最小 / 中位数 / 90% / 最大</translation>
    </message>
    <message>
        <source>Points per track min / median / 90 % / max</source>
        <translation>每条航迹点数 最小 / 中位数 / 90% / 最大</translation>
    </message>
    <message>
        <source>Longitude</source>
        <translation>经度</translation>
    </message>
    <message>
        <source>Latitude</source>
        <translation>纬度</translation>
    </message>
    <message>
        <source>Extent (east-west × north-south)</source>
        <translation>范围（东西 × 南北）</translation>
    </message>
    <message>
        <source>Area covered</source>
        <translation>覆盖面积</translation>
    </message>
    <message>
        <source>{0} (cells of {1} holding a point)</source>
        <translation>{0}（按边长 {1}的网格中有点的格子计）</translation>
    </message>
    <message>
        <source>Time</source>
        <translation>时间</translation>
    </message>
    <message>
        <source>Time span</source>
        <translation>时间跨度</translation>
    </message>
    <message>
        <source>Time window</source>
        <translation>时间窗</translation>
    </message>
    <message>
        <source>only the points in {0} – {1}</source>
        <translation>仅统计 {0} – {1} 内的点</translation>
    </message>
    <message>
        <source>At-rest spans</source>
        <translation>静止时段</translation>
    </message>
    <message>
        <source>{0} in {1}, total {2}, median {3}</source>
        <translation>{0} 段，分布于 {1}，合计 {2}，中位数 {3}</translation>
    </message>
    <message>
        <source>Maneuvers</source>
        <translation>机动</translation>
    </message>
    <message>
        <source>{0} in {1}</source>
        <translation>{0}，分布于 {1}</translation>
    </message>
    <message>
        <source>Computing…</source>
        <translation>正在计算…</translation>
    </message>
    <message>
        <source>The figures could not be computed (see the log).</source>
        <translation>无法计算统计数据（见日志）。</translation>
    </message>
    <message>
        <source>Track lifetimes</source>
        <translation>航迹持续时间</translation>
    </message>
    <message>
        <source>lifetime</source>
        <translation>持续时间</translation>
    </message>
    <message>
        <source>tracks</source>
        <translation>航迹数</translation>
    </message>
    <message>
        <source>s</source>
        <translation>秒</translation>
    </message>
    <message>
        <source>min</source>
        <translation>分钟</translation>
    </message>
    <message>
        <source>h</source>
        <translation>小时</translation>
    </message>
    <message>
        <source>d</source>
        <translation>天</translation>
    </message>
    <message>
        <source>m</source>
        <translation>米</translation>
    </message>
    <message>
        <source>km</source>
        <translation>公里</translation>
    </message>
    <message>
        <source>m²</source>
        <translation>平方米</translation>
    </message>
    <message>
        <source>km²</source>
        <translation>平方公里</translation>
    </message>
</context>
<context>
    <name>Summary</name>
    <message>
        <source>optimal</source>
        <translation>最优</translation>
    </message>
    <message>
        <source>greedy</source>
        <translation>贪心</translation>
    </message>
    <message>
        <source>sync</source>
        <translation>同步距离</translation>
    </message>
    <message>
        <source>dtw</source>
        <translation>DTW</translation>
    </message>
    <message>
        <source>dtw_whole</source>
        <translation>整航迹 DTW</translation>
    </message>
    <message>
        <source>weight</source>
        <translation>权重</translation>
    </message>
    <message>
        <source>densest</source>
        <translation>最密</translation>
    </message>
    <message>
        <source>union</source>
        <translation>并集</translation>
    </message>
    <message>
        <source>{first} and {last}</source>
        <translation>{first} 和 {last}</translation>
    </message>
    <message>
        <source>{rows:#row} in {tracks:#track} ({label}, {encoding}); {quarantined:,} quarantined</source>
        <translation>{rows:,} 行，{tracks:,} 条航迹（{label}，{encoding}）；隔离 {quarantined:,} 行</translation>
    </message>
    <message>
        <source>, {blank:#blank line} skipped</source>
        <translation>，跳过 {blank:,} 个空行</translation>
    </message>
    <message>
        <source>kept {kept:,} of {points:#point} in {tracks:#track}</source>
        <translation>保留 {points:,} 个点中的 {kept:,} 个，共 {tracks:,} 条航迹</translation>
    </message>
    <message>
        <source>; same time, another place: {rows:#row}, median {m:,.0f} m from the row kept (several targets in one batch, or times cut to the minute?)</source>
        <translation>；同一时间、另一位置：{rows:,} 行，距保留的行中位数 {m:,.0f} 米（一个批号里有多个目标，还是时间被截到了分钟？）</translation>
    </message>
    <message>
        <source>; {n:#break} split into new tracks (batch#2 …)</source>
        <translation>；{n:,} 个断点处拆分为新航迹（batch#2 …）</translation>
    </message>
    <message>
        <source>; 1 break kept: {km:,.1f} km in {s:,.0f} s, {kn:,.0f} kn, track {track} at {time}</source>
        <translation>；保留了 1 个断点：{s:,.0f} 秒内 {km:,.1f} 公里，{kn:,.0f} 节，航迹 {track}，时间 {time}</translation>
    </message>
    <message>
        <source>; 1 break kept: {km:,.1f} km at the same time, track {track} at {time}</source>
        <translation>；保留了 1 个断点：同一时刻相距 {km:,.1f} 公里，航迹 {track}，时间 {time}</translation>
    </message>
    <message>
        <source>; {n:#break} kept, the fastest {km:,.1f} km at the same time, track {track} at {time}</source>
        <translation>；保留了 {n:,} 个断点，最快的：同一时刻相距 {km:,.1f} 公里，航迹 {track}，时间 {time}</translation>
    </message>
    <message>
        <source>; {n:#break} kept, the fastest {km:,.1f} km in {s:,.0f} s, {kn:,.0f} kn, track {track} at {time}</source>
        <translation>；保留了 {n:,} 个断点，最快的：{s:,.0f} 秒内 {km:,.1f} 公里，{kn:,.0f} 节，航迹 {track}，时间 {time}</translation>
    </message>
    <message>
        <source> (--set speed.split_at_breaks=true splits there)</source>
        <translation>（勾选 参数 ▸ 清洗 ▸ 速度跳变 ▸ 在断点处拆分 会在此拆分）</translation>
    </message>
    <message>
        <source>; largest error bound {tol:,.0f} m (track {track}, noise {noise:,.0f} m; median {median:,.0f} m), farthest point {far:,.0f} m off</source>
        <translation>；最大误差界 {tol:,.0f} 米（航迹 {track}，噪声 {noise:,.0f} 米；中位数 {median:,.0f} 米），最远的点偏离 {far:,.0f} 米</translation>
    </message>
    <message>
        <source>; {n:#track} with jumps no ship can make ({legs:#leg} beyond {v:,.0f} kn; {k:,} in track {track}): clean first (wakeline clean; Clean in the window): it splits such tracks, and the error bounds then measure noise, not the jumps</source>
        <translation>；{n:,} 条航迹含有船舶不可能做到的跳变（{legs:,} 段航程超过 {v:,.0f} 节；航迹 {track} 中有 {k:,} 段）：请先清洗（wakeline clean；窗口中的“清洗”）：它会拆分这样的航迹，之后误差界衡量的是噪声，而不是跳变</translation>
    </message>
    <message>
        <source> (capped at {cap:,.0f} m on {n:#track})</source>
        <translation>（{n:,} 条航迹上限定为 {cap:,.0f} 米）</translation>
    </message>
    <message>
        <source>; removed {n:,} ({rules})</source>
        <translation>；移除 {n:,} 个（{rules}）</translation>
    </message>
    <message>
        <source>; changed {n:,} ({rules})</source>
        <translation>；修改 {n:,} 个（{rules}）</translation>
    </message>
    <message>
        <source>; replaced {n:,} ({rules})</source>
        <translation>；替换 {n:,} 个（{rules}）</translation>
    </message>
    <message>
        <source>{maneuvers:#maneuver point} in {tracks:#track} ({method})</source>
        <translation>{tracks:,} 条航迹中有 {maneuvers:,} 个机动点（{method}）</translation>
    </message>
    <message>
        <source>{n:#maneuver point}; </source>
        <translation>{n:,} 个机动点；</translation>
    </message>
    <message>
        <source>kept {kept:,} of {points:#point} ({ratio:.1%})</source>
        <translation>保留 {points:,} 个点中的 {kept:,} 个（{ratio:.1%}）</translation>
    </message>
    <message>
        <source> ({rows:#row} without a position left out)</source>
        <translation>（{rows:,} 行没有位置，未计入）</translation>
    </message>
    <message>
        <source> ({rows:#row} repeating the time and place of the row before set aside)</source>
        <translation>（{rows:,} 行与上一行的时间和位置相同，已剔除）</translation>
    </message>
    <message>
        <source>; Dis_e {dis_e:.1f} m</source>
        <translation>；Dis_e {dis_e:.1f} 米</translation>
    </message>
    <message>
        <source>, Dis_e against truth {dis_e:.1f} m</source>
        <translation>，相对真值的 Dis_e {dis_e:.1f} 米</translation>
    </message>
    <message>
        <source>{tracks:#track} -&gt; {targets:#target} ({joins:#join} of {candidates:#candidate pair}, {method})</source>
        <translation>{tracks:,} 条航迹 -&gt; {targets:,} 个目标（{candidates:,} 个候选对中连接 {joins:,} 个，{method}）</translation>
    </message>
    <message>
        <source>{n:#pair} rejected in an earlier review kept out</source>
        <translation>{n:,} 对在先前的审核中被拒绝，已排除</translation>
    </message>
    <message>
        <source>{n:#pair} split in an earlier review kept out</source>
        <translation>{n:,} 对在先前的审核中被拆分，已排除</translation>
    </message>
    <message>
        <source>; review of the earlier run: {carry}</source>
        <translation>；先前运行的审核：{carry}</translation>
    </message>
    <message>
        <source>{n:#accepted pair} proposed again, accepted</source>
        <translation>{n:,} 个已接受的配对再次被提出，已接受</translation>
    </message>
    <message>
        <source>1 accepted pair or hand merge kept as an operator link</source>
        <translation>1 个已接受的配对或手动合并保留为操作员链接</translation>
    </message>
    <message>
        <source>{n:,} accepted pairs or hand merges kept as operator links</source>
        <translation>{n:,} 个已接受的配对或手动合并保留为操作员链接</translation>
    </message>
    <message>
        <source>1 decision no longer applies (a track is gone)</source>
        <translation>1 项决定不再适用（某条航迹已不存在）</translation>
    </message>
    <message>
        <source>{n:,} decisions no longer apply (a track is gone)</source>
        <translation>{n:,} 项决定不再适用（某条航迹已不存在）</translation>
    </message>
    <message>
        <source>{n:#decision} made while the step ran taken into account</source>
        <translation>{n:,} 项在步骤运行期间做出的决定已一并计入</translation>
    </message>
    <message>
        <source>no decision to carry over</source>
        <translation>没有可沿用的决定</translation>
    </message>
    <message>
        <source>; {n:#pair} of different MMSIs kept apart (mmsi_apart; off with --set mmsi_apart=false if the ids are a sensor's own numbers)</source>
        <translation>；{n:,} 对 MMSI 不同的航迹未作候选（mmsi_apart；若批号是传感器自己的编号，用 --set mmsi_apart=false 关闭）</translation>
    </message>
    <message>
        <source>; {n:,} of the joins across gaps beyond T_gap (second look)</source>
        <translation>；其中 {n:,} 个连接跨越超过 T_gap 的间隙（二次查看）</translation>
    </message>
    <message>
        <source>; {n:,} between ends at rest (moored or at anchor)</source>
        <translation>；{n:,} 个连接位于静止的端点之间（系泊或锚泊）</translation>
    </message>
    <message>
        <source>; {n:#point} filled</source>
        <translation>；填补 {n:,} 个点</translation>
    </message>
    <message>
        <source>; warning: {plots:,} of the {tracks:,} tracks are plots, not tracks (several positions at one time: detections of several targets and clutter): their joins rest on points of different targets; join the plots into tracks first (a tracker), or read the file with batch from a column that names one target</source>
        <translation>；警告：{tracks:,} 条航迹中有 {plots:,} 条是点迹而非航迹（同一时刻有多个位置：多个目标的探测和杂波）：其连接依据的是不同目标的点；请先把点迹关联成航迹（跟踪器），或读取文件时把能标识单个目标的列作为批号</translation>
    </message>
    <message>
        <source>; warning: {plots:,} of the {tracks:,} tracks are plots, not tracks (several positions at one time: detections of several targets and clutter), so the fused tracks zig-zag between them and hold several points at {shared:,} of their {times:,} times; join the plots into tracks first (a tracker), or read the file with batch from a column that names one target</source>
        <translation>；警告：{tracks:,} 条航迹中有 {plots:,} 条是点迹而非航迹（同一时刻有多个位置：多个目标的探测和杂波），因此融合航迹在它们之间来回跳动，且在 {times:,} 个时刻中的 {shared:,} 个时刻有多个点；请先把点迹关联成航迹（跟踪器），或读取文件时把能标识单个目标的列作为批号</translation>
    </message>
    <message>
        <source>; warning: {single:,} of the {tracks:,} tracks are single fixes (a file of radar plots?): each join rests on distance and time alone, so expect wrong joins where ships are close; a tracker belongs before this step</source>
        <translation>；警告：{tracks:,} 条航迹中有 {single:,} 条只有单个定位点（雷达点迹文件？）：每个连接只依据距离和时间，船舶相近处可能连接错误；这一步之前应先经过跟踪器</translation>
    </message>
    <message>
        <source>{tracks:#track} of {sensors:#sensor} -&gt; {targets:#target} ({pairs:#pair} of {candidates:#candidate}, {distance}, {method}); {fused:#fused point}</source>
        <translation>{sensors:,} 个传感器的 {tracks:,} 条航迹 -&gt; {targets:,} 个目标（{candidates:,} 个候选中配对 {pairs:,} 对，{distance}，{method}）；{fused:,} 个融合点</translation>
    </message>
    <message>
        <source> from {n:#input point}</source>
        <translation>，来自 {n:,} 个输入点</translation>
    </message>
    <message>
        <source> (points of two sensors at one time become one)</source>
        <translation>（两个传感器同一时刻的点合并为一个）</translation>
    </message>
    <message>
        <source>; fused on every sensor's times (time_base union)</source>
        <translation>；融合于所有传感器的时刻（time_base：并集）</translation>
    </message>
    <message>
        <source>{sensor}'s {dt:g} s times</source>
        <translation>{sensor} 的 {dt:g} 秒时刻</translation>
    </message>
    <message>
        <source>{sensor}'s times</source>
        <translation>{sensor} 的时刻</translation>
    </message>
    <message>
        <source>the times of {sensors}</source>
        <translation>{sensors} 的时刻</translation>
    </message>
    <message>
        <source>; fused on {on}</source>
        <translation>；融合于 {on}</translation>
    </message>
    <message>
        <source>; fused on {on} (time_base {rule}): {lost} fix between them not kept (--time-base union keeps it)</source>
        <translation>；融合于 {on}（time_base：{rule}）：其间 {lost} 的定位点未保留（在参数面板中把多源融合的 time_base 设为 union（并集）可保留）</translation>
    </message>
    <message>
        <source>; fused on {on} (time_base {rule}): {lost} fixes between them not kept (--time-base union keeps them)</source>
        <translation>；融合于 {on}（time_base：{rule}）：其间 {lost} 的定位点未保留（在参数面板中把多源融合的 time_base 设为 union（并集）可保留）</translation>
    </message>
    <message>
        <source>; {rows:#row} repeating the time and place of the row before set aside</source>
        <translation>；{rows:,} 行与上一行的时间和位置相同，已剔除</translation>
    </message>
    <message>
        <source>; no candidate was close enough: the tracks of different sensors are farther apart than max_distance_m ({max_distance:g} m) or their times are further apart than max_interp_s ({max_interp:g} s) — raise them with --set if the sensors are that noisy or sparse</source>
        <translation>；没有足够接近的候选：不同传感器的航迹相距超过 max_distance_m（{max_distance:g} 米），或其时间相差超过 max_interp_s（{max_interp:g} 秒）——若传感器噪声大或数据稀疏，请在参数面板中调大它们</translation>
    </message>
    <message>
        <source>; {probed:#pair} of tracks came within max_distance_m ({max_distance:g} m) of each other, refused: {refused}</source>
        <translation>；{probed:,} 对航迹彼此相距在 max_distance_m（{max_distance:g} 米）以内，被拒绝：{refused}</translation>
    </message>
    <message>
        <source>{n:,} for a common span under min_overlap_s{span}</source>
        <translation>{n:,} 对因共同时段短于 min_overlap_s{span}</translation>
    </message>
    <message>
        <source>{n:,} for a common span under min_overlap_s{span} without min_overlap_fixes{fixes} of each track in at least half of it{half}</source>
        <translation>{n:,} 对因共同时段短于 min_overlap_s{span}，且在其至少一半时长{half}内每条航迹不足 min_overlap_fixes{fixes} 个点</translation>
    </message>
    <message>
        <source> ({span:g} s)</source>
        <translation>（{span:g} 秒）</translation>
    </message>
    <message>
        <source>{n:,} for a point-count ratio over count_ratio_max (or under 2 points in the common span)</source>
        <translation>{n:,} 对因点数比超过 count_ratio_max（或共同时段内不足 2 个点）</translation>
    </message>
    <message>
        <source>none by the gates</source>
        <translation>门限未拒绝任何一对</translation>
    </message>
    <message>
        <source>; </source>
        <translation>；</translation>
    </message>
    <message>
        <source>, </source>
        <translation>，</translation>
    </message>
    <message>
        <source>duplicates {n:,}</source>
        <translation>重复点 {n:,}</translation>
    </message>
    <message>
        <source>same_time {n:,}</source>
        <translation>同时异地 {n:,}</translation>
    </message>
    <message>
        <source>stationary {n:,}</source>
        <translation>静止点 {n:,}</translation>
    </message>
    <message>
        <source>speed {n:,}</source>
        <translation>速度跳变 {n:,}</translation>
    </message>
    <message>
        <source>turn {n:,}</source>
        <translation>转向异常 {n:,}</translation>
    </message>
    <message>
        <source>speed_outliers {n:,}</source>
        <translation>速度离群点 {n:,}</translation>
    </message>
    <message>
        <source>isolated {n:,}</source>
        <translation>孤立点 {n:,}</translation>
    </message>
    <message>
        <source>short_tracks {n:,}</source>
        <translation>短航迹 {n:,}</translation>
    </message>
    <message>
        <source>bspline {n:,}</source>
        <translation>B 样条 {n:,}</translation>
    </message>
    <message>
        <source>resample {n:,}</source>
        <translation>重采样 {n:,}</translation>
    </message>
    <message>
        <source>smooth {n:,}</source>
        <translation>平滑 {n:,}</translation>
    </message>
    <message>
        <source>{rule} {n:,}</source>
        <translation>{rule} {n:,}</translation>
    </message>
    <message>
        <source>; it was farther apart on average than the gate</source>
        <translation>；它的平均距离超出门限</translation>
    </message>
    <message>
        <source>; the other one was farther apart on average than the gate</source>
        <translation>；另外一对的平均距离超出门限</translation>
    </message>
    <message>
        <source>; all {n:,} were farther apart on average than the gate</source>
        <translation>；全部 {n:,} 对的平均距离都超出门限</translation>
    </message>
    <message>
        <source>; the other {n:,} were farther apart on average than the gate</source>
        <translation>；其余 {n:,} 对的平均距离超出门限</translation>
    </message>
    <message>
        <source> (the nearest {nearest:,.0f} m apart on average: raise max_distance_m with --set if the sensors are that noisy)</source>
        <translation>（最近的一对平均相距 {nearest:,.0f} 米：若传感器噪声这么大，请在参数面板中调大 max_distance_m）</translation>
    </message>
</context>
<context>
    <name>LayerName</name>
    <message>
        <source>cleaned</source>
        <translation>已清洗</translation>
    </message>
    <message>
        <source>maneuvers</source>
        <translation>机动点</translation>
    </message>
    <message>
        <source>compressed</source>
        <translation>已压缩</translation>
    </message>
    <message>
        <source>associated</source>
        <translation>已关联</translation>
    </message>
    <message>
        <source>stitched</source>
        <translation>已拼接</translation>
    </message>
    <message>
        <source>fused</source>
        <translation>已融合</translation>
    </message>
    <message>
        <source>clean</source>
        <translation>清洗</translation>
    </message>
    <message>
        <source>compress</source>
        <translation>压缩</translation>
    </message>
    <message>
        <source>associate</source>
        <translation>单源关联</translation>
    </message>
    <message>
        <source>fuse</source>
        <translation>多源融合</translation>
    </message>
    <message>
        <source>pipeline</source>
        <translation>流程</translation>
    </message>
    <message>
        <source>reviewed</source>
        <translation>已审核</translation>
    </message>
    <message>
        <source>{0} ({1})</source>
        <translation>{0}（{1}）</translation>
    </message>
    <message>
        <source>{0} and {1} more</source>
        <translation>{0} 等另 {1} 个</translation>
    </message>
</context>
<context>
    <name>ParamName</name>
    <message>
        <source>enabled</source>
        <translation>启用 enabled</translation>
    </message>
    <message>
        <source>steps</source>
        <translation>步骤 steps</translation>
    </message>
    <message>
        <source>bridge</source>
        <translation>桥接 bridge</translation>
    </message>
    <message>
        <source>window</source>
        <translation>窗口 window</translation>
    </message>
    <message>
        <source>refine</source>
        <translation>细化 refine</translation>
    </message>
    <message>
        <source>alpha</source>
        <translation>系数 alpha</translation>
    </message>
    <message>
        <source>beta</source>
        <translation>系数 beta</translation>
    </message>
    <message>
        <source>gamma</source>
        <translation>系数 gamma</translation>
    </message>
    <message>
        <source>predict</source>
        <translation>预测 predict</translation>
    </message>
    <message>
        <source>gate</source>
        <translation>波门 gate</translation>
    </message>
    <message>
        <source>sigmas</source>
        <translation>标准差倍数 sigmas</translation>
    </message>
    <message>
        <source>margin</source>
        <translation>余量 margin</translation>
    </message>
    <message>
        <source>limit</source>
        <translation>上限 limit</translation>
    </message>
    <message>
        <source>pieces</source>
        <translation>分段数 pieces</translation>
    </message>
    <message>
        <source>windows</source>
        <translation>窗口数 windows</translation>
    </message>
    <message>
        <source>method</source>
        <translation>方法 method</translation>
    </message>
    <message>
        <source>sigma</source>
        <translation>标准差 sigma</translation>
    </message>
    <message>
        <source>mode</source>
        <translation>模式 mode</translation>
    </message>
    <message>
        <source>normalize</source>
        <translation>归一化 normalize</translation>
    </message>
    <message>
        <source>stitch</source>
        <translation>拼接 stitch</translation>
    </message>
    <message>
        <source>fill</source>
        <translation>填补 fill</translation>
    </message>
    <message>
        <source>distance</source>
        <translation>距离 distance</translation>
    </message>
    <message>
        <source>glr</source>
        <translation>广义似然比 glr</translation>
    </message>
</context>
<context>
    <name>GraphicsScene</name>
    <message>
        <source>Export...</source>
        <translation>导出…</translation>
    </message>
</context>
<context>
    <name>FieldName</name>
    <message>
        <source>sensor</source>
        <translation>传感器 sensor</translation>
    </message>
    <message>
        <source>batch</source>
        <translation>批号 batch</translation>
    </message>
    <message>
        <source>time</source>
        <translation>时间 time</translation>
    </message>
    <message>
        <source>lon</source>
        <translation>经度 lon</translation>
    </message>
    <message>
        <source>lat</source>
        <translation>纬度 lat</translation>
    </message>
    <message>
        <source>speed</source>
        <translation>航速 speed</translation>
    </message>
    <message>
        <source>course</source>
        <translation>航向 course</translation>
    </message>
    <message>
        <source>truth</source>
        <translation>真值 truth</translation>
    </message>
    <message>
        <source>east</source>
        <translation>东向坐标 east</translation>
    </message>
    <message>
        <source>north</source>
        <translation>北向坐标 north</translation>
    </message>
    <message>
        <source>east_offset</source>
        <translation>东向偏移 east_offset</translation>
    </message>
    <message>
        <source>north_offset</source>
        <translation>北向偏移 north_offset</translation>
    </message>
    <message>
        <source>range</source>
        <translation>距离 range</translation>
    </message>
    <message>
        <source>bearing</source>
        <translation>方位 bearing</translation>
    </message>
    <message>
        <source>gps_week</source>
        <translation>GPS 周 gps_week</translation>
    </message>
    <message>
        <source>gps_seconds</source>
        <translation>GPS 周内秒 gps_seconds</translation>
    </message>
    <message>
        <source>target</source>
        <translation>目标 target</translation>
    </message>
    <message>
        <source>obs_lon</source>
        <translation>观测站经度 obs_lon</translation>
    </message>
    <message>
        <source>obs_lat</source>
        <translation>观测站纬度 obs_lat</translation>
    </message>
    <message>
        <source>obs_east</source>
        <translation>观测站东向坐标 obs_east</translation>
    </message>
    <message>
        <source>obs_north</source>
        <translation>观测站北向坐标 obs_north</translation>
    </message>
</context>
<context>
    <name>BearingDialog</name>
    <message>
        <source>columns by their names</source>
        <translation>按列名识别各列</translation>
    </message>
    <message>
        <source>none</source>
        <translation>无</translation>
    </message>
    <message>
        <source>A track layer of the targets (GNSS truth, AIS): each bearing goes to the track whose bearing from the observer lies within the gate, the nearest per series, track and time. A camera's series holds several targets and clutter; the detector needs one target's sequence.</source>
        <translation>目标的航迹图层（GNSS 真值、AIS）：每条方位归给从观测点看方位差在波门之内的航迹，每个序列、航迹和时刻取最近的一条。相机的序列包含多个目标和杂波；检测器需要单个目标的序列。</translation>
    </message>
    <message>
        <source>Largest bearing difference to a track</source>
        <translation>与航迹的最大方位差</translation>
    </message>
    <message>
        <source>Gate on tracks</source>
        <translation>按航迹波门关联</translation>
    </message>
    <message>
        <source>Gate</source>
        <translation>波门</translation>
    </message>
</context>
<context>
    <name>ReviewJoin</name>
    <message>
        <source>; {0} joined by hand: {1}</source>
        <translation>；手动合并 {0} 对：{1}</translation>
    </message>
    <message>
        <source>&amp;Join selected tracks</source>
        <translation>合并所选航迹(&amp;J)</translation>
    </message>
    <message>
        <source>Split selected tracks' tar&amp;get</source>
        <translation>拆分所选航迹的目标(&amp;G)</translation>
    </message>
    <message>
        <source>Join: tracks are joined in an associated layer (Run ▸ Associate first, then select its tracks)</source>
        <translation>合并：航迹在关联图层中合并（请先运行 ▸ 关联，再选择其航迹）</translation>
    </message>
    <message>
        <source>Join: the layer's review is still being read; try again</source>
        <translation>合并：仍在读取该图层的审核，请稍后再试</translation>
    </message>
    <message>
        <source>Join: select two tracks (or more) in the table</source>
        <translation>合并：请在表中选择两条（或更多）航迹</translation>
    </message>
    <message>
        <source>Join</source>
        <translation>合并</translation>
    </message>
    <message>
        <source>Join: the tracks are one target already</source>
        <translation>合并：这些航迹已是同一目标</translation>
    </message>
    <message>
        <source>Joined {0} by hand (Ctrl+Z undoes)</source>
        <translation>已手动合并 {0}（Ctrl+Z 撤销）</translation>
    </message>
    <message>
        <source>Join overlapping tracks?</source>
        <translation>合并时间重叠的航迹？</translation>
    </message>
    <message>
        <source>{0}. Join them anyway?</source>
        <translation>{0}。仍然合并？</translation>
    </message>
    <message>
        <source>Split: select a track of the target in the table</source>
        <translation>拆分：请在表中选择该目标的一条航迹</translation>
    </message>
    <message>
        <source>Split</source>
        <translation>拆分</translation>
    </message>
    <message>
        <source>Split: the track is a target of its own</source>
        <translation>拆分：该航迹本身即为一个目标</translation>
    </message>
</context>
<context>
    <name>BatchTable</name>
    <message>
        <source>joined</source>
        <translation>已连接</translation>
    </message>
    <message>
        <source>fused</source>
        <translation>已融合</translation>
    </message>
    <message>
        <source>single</source>
        <translation>单传感器</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>&amp;About Wakeline</source>
        <translation>关于 Wakeline(&amp;A)</translation>
    </message>
    <message>
        <source>&amp;Documentation</source>
        <translation>文档(&amp;D)</translation>
    </message>
    <message>
        <source>&amp;Help</source>
        <translation>帮助(&amp;H)</translation>
    </message>
    <message>
        <source>Documentation opened in the browser: {0}</source>
        <translation>已在浏览器中打开文档：{0}</translation>
    </message>
    <message>
        <source>Documentation: not installed with this copy of Wakeline</source>
        <translation>文档：此 Wakeline 副本未安装文档</translation>
    </message>
    <message>
        <source>Documentation: {0}</source>
        <translation>文档：{0}</translation>
    </message>
    <message>
        <source>In the time window: {0} of {1}, {2} of {3}</source>
        <translation>时间窗内：{1}中的 {0} 条，{3}中的 {2} 个</translation>
    </message>
    <message>
        <source>Show &amp;legend</source>
        <translation>显示图例(&amp;L)</translation>
    </message>
    <message>
        <source>The map's legend column; hidden, the map takes its width</source>
        <translation>地图的图例栏；隐藏后地图占用其宽度</translation>
    </message>
</context>
<context>
    <name>About</name>
    <message>
        <source>A desktop workbench for maritime track data: clean, detect maneuvers, compress, associate, fuse and review radar and AIS tracks.</source>
        <translation>海上航迹数据桌面工作台：对雷达与 AIS 航迹进行清洗、机动检测、压缩、关联、融合与审核。</translation>
    </message>
    <message>
        <source>About Wakeline</source>
        <translation>关于 Wakeline</translation>
    </message>
    <message>
        <source>Close</source>
        <translation>关闭</translation>
    </message>
    <message>
        <source>Data shipped with Wakeline</source>
        <translation>随 Wakeline 附带的数据</translation>
    </message>
    <message>
        <source>Demo scene: simulated (no real ships), made by wakeline simulate demo.</source>
        <translation>演示场景：模拟数据（无真实船舶），由 wakeline simulate demo 生成。</translation>
    </message>
    <message>
        <source>Licence: {0}</source>
        <translation>许可证：{0}</translation>
    </message>
    <message>
        <source>Real data Wakeline was tested on (not shipped with it)</source>
        <translation>Wakeline 测试所用的真实数据（不随软件附带）</translation>
    </message>
    <message>
        <source>Runs on: {0}</source>
        <translation>运行环境：{0}</translation>
    </message>
    <message>
        <source>Seed {0}: {1}</source>
        <translation>种子文献 {0}：{1}</translation>
    </message>
    <message>
        <source>{0}: {1}; licence: {2}</source>
        <translation>{0}：{1}；许可证：{2}</translation>
    </message>
    <message>
        <source>none stated (kept out of the product)</source>
        <translation>未声明（不随产品分发）</translation>
    </message>
    <message>
        <source>The papers its methods come from</source>
        <translation>方法所依据的论文</translation>
    </message>
    <message>
        <source>World coastline: Natural Earth 1:50m, public domain (no attribution required); made with Natural Earth.</source>
        <translation>世界海岸线：Natural Earth 1:50m，公有领域（无需署名）；Made with Natural Earth。</translation>
    </message>
</context>
<context>
    <name>ReviewJoin</name>
    <message>
        <source>{0}: {1} is not a track of this layer's review</source>
        <translation>{0}：{1} 不是本图层审核中的航迹</translation>
    </message>
</context>
<context>
    <name>TimePanel</name>
    <message>
        <source>1 layer with dates is off this slider and its window; select it to use its times</source>
        <translation>1 个日期时间图层不在此滑块及时间窗上；选中它可改用其时间</translation>
    </message>
    <message>
        <source>1 layer with scene times (T+…) is off this slider and its window; select it to use its times</source>
        <translation>1 个场景相对时间（T+…）图层不在此滑块及时间窗上；选中它可改用其时间</translation>
    </message>
    <message>
        <source>{0} layers with dates are off this slider and its window; select one to use their times</source>
        <translation>{0} 个日期时间图层不在此滑块及时间窗上；选中其一可改用其时间</translation>
    </message>
    <message>
        <source>{0} layers with scene times (T+…) are off this slider and its window; select one to use their times</source>
        <translation>{0} 个场景相对时间（T+…）图层不在此滑块及时间窗上；选中其一可改用其时间</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>&amp;Keyboard shortcuts</source>
        <translation>快捷键(&amp;K)</translation>
    </message>
    <message>
        <source>&amp;Play / pause</source>
        <translation>播放 / 暂停(&amp;P)</translation>
    </message>
    <message>
        <source>Fi&amp;nd a track (batch table filter)</source>
        <translation>查找航迹（批次表筛选）(&amp;N)</translation>
    </message>
    <message>
        <source>Filter batches (any column, or batch:4139)…</source>
        <translation>筛选批次（任意列，或 批号:4139）…</translation>
    </message>
    <message>
        <source>In the filter: select the first match and show it on the map</source>
        <translation>在筛选框中：选中第一个匹配项并在地图上显示</translation>
    </message>
    <message>
        <source>Keyboard shortcuts</source>
        <translation>快捷键</translation>
    </message>
    <message>
        <source>Leave Measure or Box zoom</source>
        <translation>退出测量或框选缩放</translation>
    </message>
    <message>
        <source>M&amp;easure range and bearing</source>
        <translation>测量距离和方位(&amp;E)</translation>
    </message>
    <message>
        <source>Name</source>
        <translation>船名</translation>
    </message>
    <message>
        <source>Plain text looks in every column; column:text in one column (batch:4139, sensor:AIS, name:argo). Enter selects the first match and shows it on the map.</source>
        <translation>普通文字在所有列中查找；“列名:文字”只在一列中查找（批号:4139、传感器:AIS、船名:argo）。回车选中第一个匹配项并在地图上显示。</translation>
    </message>
    <message>
        <source>Review: next / previous, accept / reject / split</source>
        <translation>审核：下一个 / 上一个，接受 / 拒绝 / 拆分</translation>
    </message>
    <message>
        <source>Space, ←/→ and Home act when the map or the time panel has the focus. The filter can aim at one column: batch:4139, sensor:AIS, name:argo.</source>
        <translation>空格、←/→ 和 Home 在地图或时间面板获得焦点时生效。筛选可以只查一列：批号:4139、传感器:AIS、船名:argo。</translation>
    </message>
    <message>
        <source>Step bac&amp;k</source>
        <translation>后退一步(&amp;K)</translation>
    </message>
    <message>
        <source>Step forwar&amp;d</source>
        <translation>前进一步(&amp;D)</translation>
    </message>
    <message>
        <source>Remove layer</source>
        <translation>移除图层</translation>
    </message>
    <message>
        <source>Remove layer {0}? {1}. Removing it cannot be undone.</source>
        <translation>移除图层 {0}？{1}。移除后无法撤销。</translation>
    </message>
    <message>
        <source>it carries {0} review decision(s)</source>
        <translation>它带有 {0} 条审核决策</translation>
    </message>
    <message>
        <source>{0} layer(s) were made from it</source>
        <translation>有 {0} 个图层由它生成</translation>
    </message>
    <message>
        <source>No track matches the filter</source>
        <translation>没有航迹符合筛选条件</translation>
    </message>
</context>
<context>
    <name>ReviewPanel</name>
    <message>
        <source>Pending = joined for now. A keeps the join. R: two targets, never proposed again. S: track B leaves.</source>
        <translation>待审 = 暂时已合并。A 保持合并。R：分为两个目标，不再提出。S：航迹 B 拆出。</translation>
    </message>
    <message>
        <source>cost (scaled)</source>
        <translation>代价（无量纲）</translation>
    </message>
    <message>
        <source>cost m</source>
        <translation>代价 米</translation>
    </message>
    <message>
        <source>margin (scaled)</source>
        <translation>裕度（无量纲）</translation>
    </message>
    <message>
        <source>margin m</source>
        <translation>裕度 米</translation>
    </message>
    <message>
        <source>metres between the two tracks where they meet</source>
        <translation>两条航迹相接处的距离（米）</translation>
    </message>
    <message>
        <source>pending: joined until you decide; accepted: joined; rejected: apart</source>
        <translation>待审：在您决定前保持合并；已接受：合并；已拒绝：分开</translation>
    </message>
    <message>
        <source>seconds between the end of track A and the start of track B</source>
        <translation>航迹 A 结束与航迹 B 开始之间的秒数</translation>
    </message>
    <message>
        <source>the cost of this join: metres for a fusion (mean distance between the tracks), scaled for an association</source>
        <translation>此合并的代价：融合时以米计（两航迹间的平均距离），关联时为无量纲值</translation>
    </message>
    <message>
        <source>{0} and {1}</source>
        <translation>{0} 和 {1}</translation>
    </message>
    <message>
        <source>{0} are one target now ({1} targets in all)</source>
        <translation>{0} 现在是同一个目标（共 {1} 个目标）</translation>
    </message>
    <message>
        <source>{0} are {1} targets now ({2} targets in all)</source>
        <translation>{0} 现在是 {1} 个目标（共 {2} 个目标）</translation>
    </message>
    <message>
        <source>{0} is a target of its own now ({1} targets in all)</source>
        <translation>{0} 现在单独成为一个目标（共 {1} 个目标）</translation>
    </message>
    <message>
        <source>{0} is in target {1} now ({2} targets in all)</source>
        <translation>{0} 现在属于目标 {1}（共 {2} 个目标）</translation>
    </message>
</context>
<context>
    <name>RestorePoints</name>
    <message>
        <source>restore {0} points ({1})</source>
        <translation>恢复 {0} 个点（{1}）</translation>
    </message>
    <message>
        <source>Re&amp;store points removed by cleaning on the selected tracks</source>
        <translation>恢复所选航迹上被清洗删除的点(&amp;S)</translation>
    </message>
    <message>
        <source>Restore removed points &amp;in the map's view</source>
        <translation>恢复地图视图内被删除的点(&amp;I)</translation>
    </message>
    <message>
        <source>Put the points clean removed back into the active cleaned layer (undo: Ctrl+Z); View ▸ Show points removed by cleaning shows them as ×, Box zoom frames a box</source>
        <translation>把清洗删除的点放回当前的清洗图层（撤销：Ctrl+Z）；视图 ▸ 显示被清洗删除的点 以 × 标出它们，框选缩放可框出一个区域</translation>
    </message>
    <message>
        <source>Restore: {0}</source>
        <translation>恢复：{0}</translation>
    </message>
    <message>
        <source>Took out again {0} restored points ({1}) of {2}</source>
        <translation>已从 {2} 再次移除 {0} 个恢复的点（{1}）</translation>
    </message>
    <message>
        <source>Restored {0} points removed by cleaning ({1}) into {2}</source>
        <translation>已将 {0} 个被清洗删除的点（{1}）恢复到 {2}</translation>
    </message>
    <message>
        <source>Restore: select tracks of a cleaned layer first (its points removed by cleaning are put back)</source>
        <translation>恢复：请先选择清洗图层中的航迹（其被清洗删除的点将被放回）</translation>
    </message>
    <message>
        <source>Restore: the active layer has no points removed by cleaning</source>
        <translation>恢复：当前图层没有被清洗删除的点</translation>
    </message>
    <message>
        <source>Restore: the layer changed meanwhile; nothing restored</source>
        <translation>恢复：图层在此期间已改变；未恢复任何点</translation>
    </message>
    <message>
        <source>{0} layers made from it keep the points they read: run their steps again</source>
        <translation>由它生成的 {0} 个图层仍是按原来的点计算的：请重新运行它们的步骤</translation>
    </message>
    <message>
        <source>Restore removed points in a &amp;box (drag it on the map)</source>
        <translation>恢复框内被删除的点（在地图上拖出方框）(&amp;B)</translation>
    </message>
    <message>
        <source>Restore: those points are being restored</source>
        <translation>恢复：这些点正在恢复中</translation>
    </message>
    <message>
        <source>Restore: no removed point there</source>
        <translation>恢复：该处没有被删除的点</translation>
    </message>
    <message>
        <source>Restore this point (removed by {0})</source>
        <translation>恢复此点（由{0}删除）</translation>
    </message>
    <message>
        <source>Restore all {0} points removed by {1} on {2} · {3}</source>
        <translation>恢复 {2} · {3} 上由{1}删除的全部 {0} 个点</translation>
    </message>
    <message>
        <source>Restore removed points in the map's view</source>
        <translation>恢复地图视图内被删除的点</translation>
    </message>
</context>
<context>
    <name>ReviewPanel</name>
    <message>
        <source>Δcourse °</source>
        <translation>航向差 °</translation>
    </message>
    <message>
        <source>Δspeed kn</source>
        <translation>航速差 节</translation>
    </message>
    <message>
        <source>target</source>
        <translation>目标</translation>
    </message>
    <message>
        <source>degrees between the course at the end of track A and at the start of track B (counted in full when both move at 2 kn or more: a course means little at rest)</source>
        <translation>航迹 A 结束时与航迹 B 开始时的航向之差（度；两端航速都在 2 节以上时全额计入：静止时航向意义不大）</translation>
    </message>
    <message>
        <source>knots between the speed at the end of track A and at the start of track B</source>
        <translation>航迹 A 结束时与航迹 B 开始时的航速之差（节）</translation>
    </message>
    <message>
        <source>the target track A belongs to now, as the decisions make it</source>
        <translation>航迹 A 当前所属的目标（按已做的审核决策）</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>{0} runs on {1}, which looks like radar plots (detections of each scan, see the guidance under Parameters), not ships' tracks: it takes each batch for one ship's track, and its result joins unrelated detections. Join the plots into tracks first (a tracker) for a meaningful result.</source>
        <translation>{0} 在 {1} 上运行，但它看起来是雷达点迹（每次扫描的检测，见参数下方的提示），不是船舶航迹：它把每个批次当作一条船的航迹，结果会把无关的检测连在一起。要得到有意义的结果，请先把点迹关联成航迹（跟踪器）。</translation>
    </message>
    <message>
        <source>most of it looks like radar plots, not tracks: the track steps (clean, maneuvers, compress) were not run; the screenshot shows the plots as dots</source>
        <translation>大部分看起来是雷达点迹，不是航迹：未运行航迹步骤（清洗、机动、压缩）；截图把点迹画成点</translation>
    </message>
</context>
<context>
    <name>ImportDialog</name>
    <message>
        <source>Reading the first rows…</source>
        <translation>正在读取前几行…</translation>
    </message>
</context>
<context>
    <name>ReviewDock</name>
    <message>
        <source>pending join (dashed)</source>
        <translation>待定连接（虚线）</translation>
    </message>
    <message>
        <source>accepted join</source>
        <translation>已接受的连接</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>Load s&amp;hip names (vessel table)…</source>
        <translation>加载船名(&amp;H)(船舶表)…</translation>
    </message>
    <message>
        <source>Type</source>
        <translation>船型</translation>
    </message>
    <message>
        <source>Load ship names</source>
        <translation>加载船名</translation>
    </message>
    <message>
        <source>Vessel tables (*.csv *.txt *.tsv *.gz);;All files (*)</source>
        <translation>船舶表 (*.csv *.txt *.tsv *.gz);;所有文件 (*)</translation>
    </message>
    <message>
        <source>{0}: the layer changed meanwhile; ship names not joined</source>
        <translation>{0}：图层在此期间已改变，未关联船名</translation>
    </message>
    <message>
        <source>{0}: some rows of the vessel table were not used (see the log)</source>
        <translation>{0}：船舶表有些行未使用（见日志）</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>Layer {0} restored</source>
        <translation>图层 {0} 已恢复</translation>
    </message>
    <message>
        <source>Restore removed &amp;layer {0}</source>
        <translation>恢复已移除的图层 {0}(&amp;L)</translation>
    </message>
    <message>
        <source>Restore removed &amp;layer</source>
        <translation>恢复已移除的图层(&amp;L)</translation>
    </message>
    <message>
        <source>Remove layer {0} ag&amp;ain</source>
        <translation>再次移除图层 {0}(&amp;A)</translation>
    </message>
    <message>
        <source>Remove layer ag&amp;ain</source>
        <translation>再次移除图层(&amp;A)</translation>
    </message>
    <message>
        <source>Removed layer {0}{1}; Edit ▸ Restore removed layer brings it back</source>
        <translation>已移除图层 {0}{1}；编辑 ▸ 恢复已移除的图层 可将其恢复</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>&amp;Sensors of the active layer</source>
        <translation>当前图层的传感器(&amp;S)</translation>
    </message>
    <message>
        <source>(the active layer has one sensor)</source>
        <translation>（当前图层只有一个传感器）</translation>
    </message>
    <message>
        <source>Show &amp;all sensors</source>
        <translation>显示全部传感器(&amp;A)</translation>
    </message>
    <message>
        <source>sensors hidden: {0}</source>
        <translation>已隐藏传感器：{0}</translation>
    </message>
    <message>
        <source>{0}: the view without sensors {1} could not be made; shown whole</source>
        <translation>{0}：无法生成隐藏传感器 {1} 后的视图，已完整显示</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>Show {0}</source>
        <translation>显示 {0}</translation>
    </message>
    <message>
        <source>Show or hide the tracks of sensor {0} (a view filter: the layer's points are not changed)</source>
        <translation>显示或隐藏传感器 {0} 的航迹（仅为显示筛选：图层的点不变）</translation>
    </message>
</context>
<context>
    <name>MainWindow</name>
    <message>
        <source>C&amp;hoose the active layer's colour…</source>
        <translation>选择当前图层的颜色(&amp;H)…</translation>
    </message>
    <message>
        <source>Move active layer &amp;up (drawn over the layers below)</source>
        <translation>当前图层上移(&amp;U)(画在下方图层之上)</translation>
    </message>
    <message>
        <source>Mo&amp;ve active layer down</source>
        <translation>当前图层下移(&amp;V)</translation>
    </message>
    <message>
        <source>Keep the active la&amp;yer on top</source>
        <translation>当前图层始终在最上层(&amp;Y)</translation>
    </message>
    <message>
        <source>Colour of layer {0}</source>
        <translation>图层 {0} 的颜色</translation>
    </message>
    <message>
        <source>&amp;Colour…</source>
        <translation>颜色(&amp;C)…</translation>
    </message>
    <message>
        <source>Move &amp;up</source>
        <translation>上移(&amp;U)</translation>
    </message>
    <message>
        <source>Move &amp;down</source>
        <translation>下移(&amp;D)</translation>
    </message>
    <message>
        <source>&amp;Remove</source>
        <translation>移除(&amp;R)</translation>
    </message>
    <message>
        <source>Undo &amp;layer colour ({0})</source>
        <translation>撤销图层颜色（{0}）(&amp;L)</translation>
    </message>
    <message>
        <source>Redo layer colour ({0}) ag&amp;ain</source>
        <translation>重做图层颜色（{0}）(&amp;A)</translation>
    </message>
    <message>
        <source>Undo &amp;layer move ({0})</source>
        <translation>撤销图层移动（{0}）(&amp;L)</translation>
    </message>
    <message>
        <source>Redo layer move ({0}) ag&amp;ain</source>
        <translation>重做图层移动（{0}）(&amp;A)</translation>
    </message>
    <message>
        <source>layer colour ({0})</source>
        <translation>图层颜色（{0}）</translation>
    </message>
    <message>
        <source>layer move ({0})</source>
        <translation>图层移动（{0}）</translation>
    </message>
    <message>
        <source>remove layer {0}</source>
        <translation>移除图层 {0}</translation>
    </message>
</context>
<context>
    <name>WindowWords</name>
    <message>
        <source>{0} ▸ {1} ▸ {2} ({3})</source>
        <translation>{0} ▸ {1} ▸ {2}（{3}）</translation>
    </message>
    <message>
        <source>ticked</source>
        <translation>勾选</translation>
    </message>
    <message>
        <source>unticked</source>
        <translation>不勾选</translation>
    </message>
</context>
</TS>
